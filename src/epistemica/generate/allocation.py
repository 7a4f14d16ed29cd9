"""Family ``allocation``: every robot at a goal of its own; nobody says which.

Drawn per mission: team 2-4, goals from the team's size to one more (so that a robot's
decision space stays below a thousand configurations), the team, goals, walls and sensing
of :func:`~epistemica.generate.team.draw_team`, and who sees a robot settle.

Examples
--------
>>> d = draw(np.random.default_rng(3))
>>> d.lines[0], d.parameters["goals"] >= d.parameters["robots"]
('mission allocation', True)
"""

from __future__ import annotations

import numpy as np

from epistemica.generate.common import Draw
from epistemica.generate.team import PLAIN, Options, goal_mission

__all__ = ["SUMMARY", "draw"]

SUMMARY = "Allocation: every robot at a goal of its own, pairwise distinct."


def draw(rng: np.random.Generator, options: Options = PLAIN) -> Draw:
    """One allocation mission (its lines, without the header)."""
    n = int(rng.integers(2, 5))
    return goal_mission("allocation", rng, n, n + int(rng.integers(0, 2)), options)
