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

from epistemica.sim.policies.levels import REASONING
from epistemica.sim.study.trace import known_goals

__all__ = [
    "LEVEL_COLOURS",
    "ROBOT_COLOURS",
    "fetching_robot",
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


def level_style(level: str) -> tuple[str, str, str]:
    """``(colour, line style, marker)`` of a reasoning level, the same in every figure
    (fixed by the level's place in :data:`~epistemica.sim.policies.levels.REASONING`; a level not
    there takes a place after them by its name). Two levels never share all three.

    Examples
    --------
    >>> level_style("third") == level_style("third"), level_style("zero") != level_style("first")
    (True, True)
    """
    if level in REASONING:
        k = REASONING.index(level)
    else:
        k = len(REASONING) + sum(map(ord, level)) % 31
    return LEVEL_COLOURS[k % 10], _LINES[k % 4], _MARKERS[k % len(_MARKERS)]


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
    known = known_goals(trace)
    if known is not None:
        own = np.diagonal(known, axis1=1, axis2=2).transpose(0, 2, 1)  # (T, n, m)
        private = (own[:, :, None, :] & ~known).sum(axis=(0, 2, 3))
        if private.max() > 0:
            return int(np.argmax(private))
    modelled = np.asarray(trace["modelled"], dtype=float)
    if modelled.size == 0:
        return 0
    own = np.asarray(trace["considered"], dtype=float)
    gap = np.abs(modelled - own[:, None, :]).sum(axis=(0, 2))
    return int(np.argmax(gap)) if gap.max() > 0 else 0
