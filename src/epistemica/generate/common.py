"""What every family of generated missions shares: drawing places, obstacles, sensors and
the mission file's header.

A family module draws one mission from a seeded :class:`numpy.random.Generator` and writes
it as ordinary mission-file text (docs/language.md, "Mission files") built from the lines
below; every number is rounded to a tenth of a metre, so the file is short to read and the
same seed gives the same bytes.

Examples
--------
>>> rng = np.random.default_rng(0)
>>> walls = draw_obstacles(rng, 30.0, 2)
>>> len(walls), len(draw_points(rng, 3, 30.0, walls, gap=2.0))
(2, 3)
>>> obstacle_line(((1.0, 2.0), (3.0, 2.0), (3.0, 4.0), (1.0, 4.0)))
'obstacle (1, 2) (3, 2) (3, 4) (1, 4)'
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "Draw",
    "draw_obstacles",
    "draw_points",
    "header",
    "number",
    "obstacle_line",
    "point",
    "sensor_names",
]

#: How far (m) a robot or goal keeps from every obstacle.
MARGIN = 1.5

Rectangle = tuple[tuple[float, float], ...]


class Draw:
    """What a family draws for one mission: its parameters (for the header) and its lines."""

    def __init__(self) -> None:
        self.parameters: dict[str, object] = {}
        self.lines: list[str] = []

    def note(self, **values: object) -> None:
        """Record drawn parameters (they appear in the header, in this order)."""
        self.parameters.update(values)

    def add(self, *lines: str) -> None:
        self.lines.extend(lines)


def number(x: float) -> str:
    """``x`` rounded to a tenth, without a trailing ``.0``."""
    text = f"{round(float(x), 1):.1f}"
    return text[:-2] if text.endswith(".0") else text


def point(xy: Sequence[float]) -> str:
    """``(x, y)`` as a mission file writes a place."""
    return f"({number(xy[0])}, {number(xy[1])})"


def obstacle_line(corners: Rectangle) -> str:
    """The ``obstacle`` statement of a polygon's corners."""
    return "obstacle " + " ".join(point(c) for c in corners)


def draw_obstacles(rng: np.random.Generator, workspace: float, count: int) -> list[Rectangle]:
    """``count`` axis-aligned walls, 2-8 m by 1-4 m (either way round), inside the workspace
    less 3 m borders."""
    out = []
    for _ in range(count):
        w, h = rng.uniform(2.0, 8.0), rng.uniform(1.0, 4.0)
        if rng.random() < 0.5:
            w, h = h, w
        x = round(rng.uniform(3.0, workspace - 3.0 - w), 1)
        y = round(rng.uniform(3.0, workspace - 3.0 - h), 1)
        x1, y1 = round(x + w, 1), round(y + h, 1)
        out.append(((x, y), (x1, y), (x1, y1), (x, y1)))
    return out


def _clear(p: np.ndarray, walls: Sequence[Rectangle]) -> bool:
    for c in walls:
        (x0, y0), (x1, y1) = c[0], c[2]
        if x0 - MARGIN <= p[0] <= x1 + MARGIN and y0 - MARGIN <= p[1] <= y1 + MARGIN:
            return False
    return True


def draw_points(
    rng: np.random.Generator,
    count: int,
    workspace: float,
    walls: Sequence[Rectangle] = (),
    *,
    gap: float = 0.0,
    taken: Sequence[Sequence[float]] = (),
) -> list[tuple[float, float]]:
    """``count`` places uniform in the workspace less 1 m borders, rounded to a tenth, clear
    of the walls by :data:`MARGIN` and at least ``gap`` m from each other and from
    ``taken`` (rejection sampling: at most 10,000 tries)."""
    out: list[tuple[float, float]] = []
    others = [np.asarray(t, dtype=float) for t in taken]
    for _ in range(10_000):
        if len(out) == count:
            return out
        p = np.round(rng.uniform(1.0, workspace - 1.0, size=2), 1)
        if not _clear(p, walls):
            continue
        if gap and any(np.hypot(*(p - q)) < gap for q in others):
            continue
        out.append((float(p[0]), float(p[1])))
        others.append(p)
    raise InvalidArgumentError(
        f"no room for {count} places in a {workspace} m workspace", hint="fewer obstacles"
    )


def sensor_names(rng: np.random.Generator, robots: int) -> list[str]:
    """One sensor per robot, range or bearing with probability 1/2."""
    return [("range", "bearing")[int(k)] for k in rng.integers(0, 2, size=robots)]


def header(command: str, seed: int, parameters: dict[str, object], summary: str) -> list[str]:
    """The comment lines a generated mission starts with: the family and options
    (``command``), the seed and the drawn parameters."""
    drawn = ", ".join(f"{k} {v}" for k, v in parameters.items())
    lines = [
        f"# Generated mission, generator seed {seed}: `epistemica generate {command}",
        f"# --count 1 --seed {seed}` writes this file again, byte for byte.",
        f"# {summary}",
    ]
    words, line = drawn.split(" "), "# Drawn:"
    for word in words:
        if len(line) + len(word) + 1 > 92:
            lines.append(line)
            line = "#  "
        line += " " + word
    return [*lines, line]
