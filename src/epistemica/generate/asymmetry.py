"""Family ``asymmetry``: who knows which goals, and who saw which event, drawn at random.

A rendezvous (probability 0.6) or an allocation. Drawn per mission: team 3-4 (allocation
2-3), open goals from the team's size to two more, 0-2 goals closed at the start, the team,
goals, walls and sensing of :func:`~epistemica.generate.team.draw_team`; each robot knows
each open goal with one probability drawn per mission (0.3-0.9; at least one goal, or in
an allocation as many as the team), so goals come out private, partly shared or common by
chance; 0-2 events at steps 0-30, each a closure (a goal closes) or a relocation (a goal
closes and a closed one opens), observed in full by a random subset of the robots (or by
those near the goal), maybe partially by some others. Nothing is arranged so that one
level wins.

Examples
--------
>>> d = draw(np.random.default_rng(5))
>>> d.lines[0] in ("mission rendezvous", "mission allocation")
True
"""

from __future__ import annotations

import numpy as np

from epistemica.generate.common import Draw
from epistemica.generate.team import PLAIN, STUDY, Options, draw_team
from epistemica.sim.kinds.goal import ALLOCATION, RENDEZVOUS

__all__ = ["SUMMARY", "draw"]

SUMMARY = "Knowledge asymmetry: goals known to random robots, events seen by random subsets."


def _subset(rng: np.random.Generator, names: list[str], p: float, at_least: int = 1) -> list[str]:
    """Each of ``names`` with probability ``p``; at least ``at_least`` of them."""
    keep = rng.random(len(names)) < p
    missing = at_least - int(keep.sum())
    if missing > 0:
        keep[rng.choice(np.flatnonzero(~keep), size=missing, replace=False)] = True
    return [name for name, k in zip(names, keep, strict=True) if k]


def _knows(d: Draw, rng: np.random.Generator, robots: list[str], goals: list[str], least: int):
    p = round(float(rng.uniform(0.3, 0.9)), 2)
    d.note(knows_probability=p)
    for r in robots:
        d.add(f"knows {r}: {', '.join(_subset(rng, goals, p, least))}")


def _observers(rng: np.random.Generator, robots: list[str], goal: str) -> list[str]:
    """The observer lines of an event about ``goal``."""
    if rng.random() < 0.3:
        return [f"    full robots if near({goal}, {int(rng.integers(4, 13))})"]
    full = _subset(rng, robots, float(rng.uniform(0.2, 0.8)))
    lines = [f"    full {', '.join(full)}"]
    rest = [r for r in robots if r not in full]
    if rest and rng.random() < 0.3:
        lines.append(f"    partial {', '.join(_subset(rng, rest, 0.5))}")
    return lines


def draw(rng: np.random.Generator, options: Options = PLAIN) -> Draw:
    """One knowledge-asymmetry mission (its lines, without the header)."""
    d = Draw()
    kind = RENDEZVOUS if rng.random() < 0.6 else ALLOCATION
    n = int(rng.integers(3, 5)) if kind.gathers else int(rng.integers(2, 4))
    m, spare = n + int(rng.integers(0, 3)), int(rng.integers(0, 3))
    d.add(f"mission {kind.name}")
    d.note(kind=kind.name)
    team = draw_team(d, rng, n, m + spare, options, frozenset(range(m, m + spare)))
    open_goals, closed = team.goals[:m], team.goals[m:]
    _knows(d, rng, team.robots, open_goals, 1 if kind.gathers else n)
    d.add("event settle seen by nearby")
    least = 1 if kind.gathers else n  # open goals the mission needs
    events = []
    for e in range(int(rng.integers(0, 3))):
        can_close = len(open_goals) > least
        if not can_close and not closed:
            break
        goal = str(rng.choice(open_goals))
        step = int(rng.integers(0, 31))
        if closed and (not can_close or rng.random() < 0.5):  # a relocation
            new = closed.pop(0)
            open_goals = [g for g in open_goals if g != goal] + [new]
            body = [f"closes {goal}", f"opens {new}", f"announces closed({goal})", f"reveals {new}"]
            events.append(f"relocate {goal}->{new} at {step}")
        else:
            open_goals = [g for g in open_goals if g != goal]
            body = [f"closes {goal}", f"announces closed({goal})"]
            events.append(f"close {goal} at {step}")
        d.add(f"event change{e + 1} {{", f"    when step {step}")
        d.add(*(f"    {line}" for line in body), *_observers(rng, team.robots, goal), "}")
    d.note(events="; ".join(events) or "none")
    d.add(STUDY)
    return d
