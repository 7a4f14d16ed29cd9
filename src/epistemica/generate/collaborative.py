"""Family ``collaborative``: tasks found while exploring, each needing several robots at once.

Drawn per mission: team 3-8, tasks 2-6 each needing 2-4 robots (at most the team), workspace
25-60 m, sight 5-12 m, robots and tasks at random places (tasks at least 2 m apart), each
robot's sensor, and which of the ``waiting`` and ``heading`` events the mission has (each
with probability 0.8; ``found`` and ``done`` always). The step limit grows with the area
to sweep: 400 steps plus 1 per 10 m² of workspace above 30 m x 30 m. The collaborative
simulator has no obstacles and no disc robots yet, so this family draws neither.

Examples
--------
>>> d = draw(np.random.default_rng(2))
>>> d.lines[0], 3 <= d.parameters["robots"] <= 8
('mission collaborative', True)
"""

from __future__ import annotations

import numpy as np

from epistemica.generate.common import Draw, draw_points, number, point, sensor_names
from epistemica.generate.team import PLAIN, Options

__all__ = ["SUMMARY", "draw"]

SUMMARY = "Collaborative tasks: found while exploring, done when enough robots stand at one."

_EVENTS = {
    "found": ("a robot that comes within sight of a task finds it", "r within {sight} of t"),
    "waiting": ("a robot standing at a task waits for help", "r settles at t"),
    "heading": ("a robot moving towards a task shows where it goes", "r heads to t"),
}


def _event(name: str, sight: str) -> list[str]:
    why, when = _EVENTS[name]
    return [
        f"# {why}",
        f"event {name}(r in robots, t in tasks) {{",
        f"    when {when.format(sight=sight)}",
        "    reveals t",
        "    full robots if sees(r)",
        "}",
    ]


def draw(rng: np.random.Generator, options: Options = PLAIN) -> Draw:
    """One collaborative mission (its lines, without the header)."""
    del options  # checked by the registry: this family has neither
    d = Draw()
    n, m = int(rng.integers(3, 9)), int(rng.integers(2, 7))
    workspace = float(rng.integers(25, 61))
    sight = float(rng.integers(5, 13))
    needs = [int(k) for k in rng.integers(2, min(4, n) + 1, size=m)]
    starts = draw_points(rng, n, workspace)
    tasks = draw_points(rng, m, workspace, gap=2.0)
    sensors = sensor_names(rng, n)
    events = ["found"] + [e for e in ("waiting", "heading") if rng.random() < 0.8]
    steps = 400 + max(0, int((workspace**2 - 900) / 10))
    d.note(robots=n, tasks=m, needs="/".join(map(str, needs)), workspace=int(workspace))
    d.note(sight=int(sight), events="+".join(events), steps=steps)
    d.add("mission collaborative", f"workspace {int(workspace)}")
    for i, (sensor, xy) in enumerate(zip(sensors, starts, strict=True)):
        d.add(f"robot r{i + 1}: {sensor} at {point(xy)}")
    for j, (xy, k) in enumerate(zip(tasks, needs, strict=True)):
        d.add(f"task t{j + 1} at {point(xy)} needs {k}")
    d.add(f"sensing range {number(sight)}")
    for name in events:
        d.add(*_event(name, number(sight)))
    d.add(
        "# a task is done when enough robots stand at it at once: those who see them know",
        "event done(t in tasks) {",
        "    when t is reached",
        "    closes t",
        "    announces closed(t)",
        "    full robots if sees(reachers)",
        "}",
        f"simulate trials 2 seed 0 steps {steps} radius 1.5",
    )
    return d
