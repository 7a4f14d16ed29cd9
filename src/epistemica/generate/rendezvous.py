"""Family ``rendezvous``: the whole team meets at one goal; nobody says which.

Drawn per mission: team 2-5, goals 2-5 (every goal known to every robot), the team, goals,
walls and sensing of :func:`~epistemica.generate.team.draw_team`, and whether a robot seen
standing at a goal is seen by the robots near it or by every robot.

Examples
--------
>>> d = draw(np.random.default_rng(3))
>>> d.lines[0], d.parameters["settle_seen_by"] in ("nearby", "everyone")
('mission rendezvous', True)
"""

from __future__ import annotations

import numpy as np

from epistemica.generate.common import Draw
from epistemica.generate.team import PLAIN, Options, goal_mission

__all__ = ["SUMMARY", "draw"]

SUMMARY = "Rendezvous: every robot within the success radius of one common goal."


def draw(rng: np.random.Generator, options: Options = PLAIN) -> Draw:
    """One rendezvous mission (its lines, without the header)."""
    n = int(rng.integers(2, 6))
    return goal_mission("rendezvous", rng, n, int(rng.integers(2, 6)), options)
