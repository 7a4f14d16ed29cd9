"""The colours of robots in every figure and page, and which robot's nested sets to show.

Goals are black or grey everywhere; robots take :data:`ROBOT_COLOURS`, a qualitative
palette (matplotlib's ``tab10``) without its grey, so that a colour always means a robot.

Examples
--------
>>> robot_colour(0), robot_colour(len(ROBOT_COLOURS))
('#1f77b4', '#1f77b4')
"""

from __future__ import annotations

from typing import Any

import numpy as np

from epistemica.sim.policies.levels import KIND_LEVELS, REASONING
from epistemica.sim.study.trace import known_goals

__all__ = [
    "LEVEL_COLOURS",
    "ROBOT_COLOURS",
    "TYPE_MEANINGS",
    "fetching_robot",
    "focus_reason",
    "focus_robot",
    "level_style",
    "robot_colour",
]

#: A qualitative palette without grey or black (those are the goals').
ROBOT_COLOURS = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
)


#: Level colours (matplotlib's ``tab10``), by a level's place in
#: :data:`~epistemica.sim.policies.levels.REASONING`: a level has one colour in every figure.
LEVEL_COLOURS = (
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
)  # fmt: skip
_LINES = ("-", "--", "-.", ":")
# One marker per level of REASONING (greyscale readers tell the levels apart by it).
_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*", "p", "h", "<", ">", "d", "8", "H",
            "1", "2", "3", "4", "+")  # fmt: skip


#: What each behaviour of the teammate-model library (:data:`epistemica.aif.teammates.TYPES`)
#: means, in the words the figures and pages print beside a robot's posterior over them.
TYPE_MEANINGS = {
    "team": "reasons as the team does (the team prior)",
    "greedy": "heads for the goal nearest to it",
    "convention": "least total travel, ties broken the other way",
    "stationary": "stays where it is",
}


#: The levels most often drawn side by side (the main job's and the default studies'):
#: the first places, so that each has a colour of its own.
_SHOWN_FIRST = ("third", "convention", "rules-first", "rules-third-shared", "rules-third",
                "first", "second", "zero", "third-shared", "third-priormode")  # fmt: skip
#: Every level of every kind, in the order their styles are given.
_ORDER = tuple(dict.fromkeys((*_SHOWN_FIRST, *REASONING, *(n for t in KIND_LEVELS.values()
                                                           for n in t))))  # fmt: skip
#: Collaborative levels drawn beside those: the rules take the rules' colour, the oracle
#: one the collaborative study leaves free.
_COLOUR_OF = {"rules": 4, "rules-shared": 3, "oracle": 6}


def level_style(level: str) -> tuple[str, str, str]:
    """``(colour, line style, marker)`` of a reasoning level, the same in every figure
    (fixed by the level's place in :data:`_ORDER`: the levels most often compared first,
    then :data:`~epistemica.sim.policies.levels.REASONING` and the other kinds' levels; a
    level not there takes a place after them by its name). Two registered levels never
    share all three (up to 40 of them), and the levels of one default study never share a
    colour.

    Examples
    --------
    >>> level_style("third") == level_style("third"), level_style("third") != level_style("first")
    (True, True)
    >>> shown = ("convention", "rules-first", "rules-third", "third")
    >>> len({level_style(name)[0] for name in shown})
    4
    """
    if level in _ORDER:
        k = _ORDER.index(level)
    else:
        k = len(_ORDER) + sum(map(ord, level)) % 31
    colour = _COLOUR_OF.get(level, k % 10)
    return LEVEL_COLOURS[colour], _LINES[(k // 10) % 4], _MARKERS[k % len(_MARKERS)]


def robot_colour(i: int) -> str:
    """The colour of robot ``i`` (0-based) in every figure and the browser view."""
    return ROBOT_COLOURS[i % len(ROBOT_COLOURS)]


def fetching_robot(trace: dict[str, Any]) -> int:
    """The robot whose nested knowledge a joint trial's picture shows first: the one that
    fetched a teammate on the most steps (its reason to fetch is a teammate that does not
    know; the lowest index on a tie, robot 0 if none did).

    Examples
    --------
    >>> fetching_robot({"robots": ["a", "b", "c"], "steer_to": [[-1, -2, 0], [-2, -2, 0]]})
    1
    """
    steer = np.asarray(trace["steer_to"], dtype=int).reshape(-1, len(trace["robots"]))
    return int(np.argmax((steer == -2).sum(axis=0)))


def _private(trace: dict[str, Any]) -> np.ndarray | None:
    """``(n, n, m)`` steps on which robot ``i`` knew of goal ``g`` and took robot ``j`` not
    to know of it (``None`` without the trace's ``knows``)."""
    known = known_goals(trace)
    if known is None:
        return None
    own = np.diagonal(known, axis1=1, axis2=2).transpose(0, 2, 1)  # (T, n, m)
    return (own[:, :, None, :] & ~known).sum(axis=0)


def focus_robot(trace: dict[str, Any]) -> int:
    """The robot whose knowledge decides the trial, whose nested reasoning the figures show:
    the one that most often knows of a goal it takes a teammate not to know of (private
    knowledge, the trace's ``knows``); without any, the robot whose model of its
    teammates' sets differs most from their own sets (the first robot when no model
    differs).

    Examples
    --------
    >>> focus_robot({"modelled": [[[4, 4], [3, 4]]], "considered": [[4, 4]]})
    1
    >>> focus_robot({"modelled": [], "considered": []})
    0
    >>> focus_robot({"modelled": [], "considered": [], "steps": 1, "robots": ["a", "b"],
    ...              "goals": ["x"], "knows": [[0, 1, 1, 0, 1, "start"]]})
    1
    """
    private = _private(trace)
    if private is not None and private.max() > 0:
        return int(np.argmax(private.sum(axis=(1, 2))))
    modelled = np.asarray(trace["modelled"], dtype=float)
    if modelled.size == 0:
        return 0
    own = np.asarray(trace["considered"], dtype=float)
    gap = np.abs(modelled - own[:, None, :]).sum(axis=(0, 2))
    return int(np.argmax(gap)) if gap.max() > 0 else 0


def focus_reason(trace: dict[str, Any]) -> str:
    """Why :func:`focus_robot` chose its robot, in words computed from the trace: what it
    knew of that it took which teammates not to know of, and on how many steps.

    Examples
    --------
    >>> focus_reason({"modelled": [], "considered": [], "steps": 2, "robots": ["a", "b"],
    ...               "goals": ["x", "y"], "knows": [[0, 1, 1, 0, 1, "start"],
    ...               [0, 1, 1, 1, 1, "start"], [0, 1, 0, 1, 1, "start"]]})
    'b is shown first: it knows of x and takes a not to know of it (on 2 of 2 steps)'
    >>> focus_reason({"modelled": [], "considered": [], "robots": ["a", "b"]})
    'a is shown first: no robot models a teammate differently from its own set'
    """
    f, robots = focus_robot(trace), list(trace["robots"])
    private = _private(trace)
    if private is not None and private[f].max() > 0:
        goals = [g for g, c in zip(trace["goals"], private[f].max(axis=0), strict=True) if c]
        who = [robots[j] for j in range(len(robots)) if private[f, j].max() > 0]
        steps = int(private[f].max())
        return (
            f"{robots[f]} is shown first: it knows of {_words(goals)} and takes "
            f"{_words(who)} not to know of {'it' if len(goals) == 1 else 'them'} "
            f"(on {steps} of {max(int(trace['steps']), 1)} steps)"
        )
    modelled = np.asarray(trace["modelled"], dtype=float)
    if modelled.size and np.abs(modelled - np.asarray(trace["considered"])[:, None]).max() > 0:
        return (
            f"{robots[f]} is shown first: its model of its teammates' configuration sets "
            "differs most from their own sets"
        )
    return f"{robots[f]} is shown first: no robot models a teammate differently from its own set"


def _words(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
