"""Contacts: disc robots that cannot overlap, and polygonal obstacles that block motion and
sight.

Both are optional (``Scenario(robot_radius=..., obstacles=...)``, or a mission file's
``robot ... radius R`` and ``obstacle (x, y) (x, y) (x, y) ...`` lines); a scenario with
neither runs exactly as before. After the dynamics moved every robot (and process noise
and the workspace bound were applied), :func:`resolve_contacts` cuts each robot's move
short, robot by robot in index order, at the last point of its straight path from where it
was that keeps it

- at least its radius away from every obstacle (a point robot, radius 0, keeps 1 µm), and
- at least the sum of the radii away from every teammate (the teammates before it at their
  new places, the ones after it at their old places). Two robots that start closer than
  that may not come closer still; they may separate.

A disc stopped by a teammate it touches slides along it (frictionless discs): the rest of
its move, less the part that presses into that teammate, is cut again the same way. Without
the slide two discs that graze each other on their way to one goal push into each other for
good (a generated rendezvous did so to the step limit at every level).

The cut is found by bisection on the fraction of the move (the swept path only grows with
it, so "blocked" is monotone), to 2⁻³⁰ of the move. The heading is the one the dynamics
gave. :func:`line_of_sight` says which robots see each other past the obstacles: the
simulator observes a teammate, and an event's ``sees(X)`` holds, only in sight.

Examples
--------
A wall between two robots stops the first and hides them from each other:

>>> wall = polygon([[4, -5], [5, -5], [5, 5], [4, 5]])
>>> before, after = np.array([[0.0, 0, 0], [9, 0, 0]]), np.array([[6.0, 0, 0], [9, 0, 0]])
>>> resolve_contacts(before, after, np.zeros(2), (wall,))[0, 0].round(4)
np.float64(4.0)
>>> line_of_sight(before[:, :2], (wall,)).tolist()
[[True, False], [False, True]]
"""

from __future__ import annotations

import numpy as np

from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "inside",
    "line_of_sight",
    "polygon",
    "polygon_distance",
    "resolve_contacts",
    "segment_distances",
]

#: Clearance (m) a point robot keeps from obstacles, so that it never sits on an edge.
CLEARANCE = 1e-6
_BISECTIONS = 30


def polygon(points) -> np.ndarray:
    """A validated obstacle: ``(k, 2)`` vertices in order, ``k >= 3``, non-zero area.

    Examples
    --------
    >>> polygon([[0, 0], [1, 0], [0, 1]]).shape
    (3, 2)
    >>> polygon([[0, 0], [1, 1], [2, 2]])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    epistemica.del_.errors.InvalidArgumentError: obstacle [[0.0, 0.0], ...] has no area
    hint: give at least three corners that are not on one line
    """
    try:
        p = np.array(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidArgumentError(
            f"an obstacle must be (x, y) corners, got {points!r}",
            hint="e.g. [[0, 0], [1, 0], [0, 1]]",
        ) from exc
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3 or not np.all(np.isfinite(p)):
        raise InvalidArgumentError(
            f"an obstacle needs at least 3 finite (x, y) corners, got shape {p.shape}",
            hint="e.g. [[0, 0], [1, 0], [0, 1]]",
        )
    x, y = p[:, 0], p[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    if area < 1e-12:
        raise InvalidArgumentError(
            f"obstacle {p.tolist()} has no area",
            hint="give at least three corners that are not on one line",
        )
    p.setflags(write=False)
    return p


def _edges(poly: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return poly, np.roll(poly, -1, axis=0)


def inside(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """``(p,)`` booleans: each of the ``(p, 2)`` points lies inside the polygon (even-odd)."""
    a, b = _edges(poly)
    px, py = points[:, None, 0], points[:, None, 1]
    crosses = (a[:, 1] > py) != (b[:, 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = a[:, 0] + (py - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return np.count_nonzero(crosses & (px < x_at), axis=1) % 2 == 1


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances from points ``p (..., 2)`` to segments ``a b (..., 2)`` (broadcast)."""
    ab = b - a
    length = np.maximum(np.einsum("...i,...i->...", ab, ab), 1e-300)
    t = np.clip(np.einsum("...i,...i->...", p - a, ab) / length, 0.0, 1.0)
    closest = a + t[..., None] * ab
    return np.hypot(*np.moveaxis(p - closest, -1, 0))


def _cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1]) - (a[..., 1] - o[..., 1]) * (
        b[..., 0] - o[..., 0]
    )


def _intersect(p0, p1, a, b) -> np.ndarray:
    """Segments ``p0 p1`` and ``a b`` cross or touch (broadcast)."""
    d1, d2 = _cross(a, b, p0), _cross(a, b, p1)
    d3, d4 = _cross(p0, p1, a), _cross(p0, p1, b)
    return (d1 * d2 <= 0) & (d3 * d4 <= 0) & ~((d1 == 0) & (d2 == 0) & (d3 == 0) & (d4 == 0))


def segment_distances(p0: np.ndarray, p1: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """``(p,)`` distances from the segments ``p0 p1`` (each ``(p, 2)``) to the polygon:
    :func:`polygon_distance` of each, at once."""
    a, b = _edges(poly)
    e0, e1 = p0[:, None], p1[:, None]
    touch = _intersect(e0, e1, a[None], b[None]).any(axis=1) | inside(p1, poly)
    near = np.minimum(_point_segment(e0, a[None], b[None]), _point_segment(e1, a[None], b[None]))
    near = np.minimum(near, _point_segment(a[None], e0, e1)).min(axis=1)
    return np.where(touch, 0.0, near)


def polygon_distance(p0: np.ndarray, p1: np.ndarray, poly: np.ndarray) -> float:
    """Distance from the segment ``p0 p1`` to the polygon (0 if they touch or the segment
    ends inside)."""
    a, b = _edges(poly)
    if _intersect(p0, p1, a, b).any() or inside(p1[None], poly)[0]:
        return 0.0
    return float(
        min(
            _point_segment(p0, a, b).min(),
            _point_segment(p1, a, b).min(),
            _point_segment(a, p0, p1).min(),
        )
    )


def line_of_sight(points: np.ndarray, obstacles, targets: np.ndarray | None = None):
    """``(n, k)`` booleans: the segment from point ``i`` to target ``j`` crosses no obstacle
    edge. Without ``targets``, the points see each other (``(n, n)``, each sees itself)."""
    ends = points if targets is None else targets
    clear = np.ones((points.shape[0], ends.shape[0]), dtype=bool)
    p0, p1 = points[:, None, None, :], ends[None, :, None, :]
    for poly in obstacles:
        a, b = _edges(poly)
        clear &= ~_intersect(p0, p1, a[None, None], b[None, None]).any(axis=-1)
    if targets is None:
        np.fill_diagonal(clear, True)
    return clear


def _blocked(i, start, end, placed, radii, obstacles, gaps) -> bool:
    """Robot ``i``'s straight move ``start -> end`` comes too close to an obstacle or to a
    teammate (at ``placed``)."""
    for poly in obstacles:
        if polygon_distance(start, end, poly) < max(radii[i], CLEARANCE):
            return True
    if gaps is None:
        return False
    others = np.flatnonzero(gaps > 0)
    if others.size == 0:
        return False
    d = _point_segment(placed[others], start[None], end[None])
    return bool(np.any(d < gaps[others]))


def _cut(i, start, end, placed, radii, obstacles, discs: bool) -> np.ndarray:
    """The last point of robot ``i``'s straight move ``start -> end`` that touches
    nothing (bisected: the swept path only grows with the fraction)."""
    gaps = None
    if discs:
        gaps = np.minimum(radii[i] + radii, np.hypot(*(placed - start).T))
        gaps[i] = 0.0
    if not _blocked(i, start, end, placed, radii, obstacles, gaps):
        return end
    low, high = 0.0, 1.0
    for _ in range(_BISECTIONS):
        middle = 0.5 * (low + high)
        if _blocked(i, start, start + middle * (end - start), placed, radii, obstacles, gaps):
            high = middle
        else:
            low = middle
    return start + low * (end - start)


def _slide(i, point, end, placed, radii) -> np.ndarray:
    """Where robot ``i``, stopped at ``point`` short of ``end``, goes instead: the rest of
    its move without the part that presses into the teammate it touches (the nearest
    within its contact distance), as frictionless discs slide; ``point`` if none."""
    rest = end - point
    away = point - placed
    distance = np.hypot(*away.T)
    touching = distance <= (radii[i] + radii) * (1 + 1e-6) + 1e-9
    touching[i] = False
    if not touching.any():
        return point
    j = np.flatnonzero(touching)[np.argmin(distance[touching])]
    normal = away[j] / max(distance[j], 1e-12)
    into = float(rest @ normal)
    return point + (rest - into * normal if into < 0 else rest)


def resolve_contacts(
    before: np.ndarray, after: np.ndarray, radii: np.ndarray, obstacles=()
) -> np.ndarray:
    """The ``(n, 3)`` poses after contacts: each robot's move ``before -> after`` cut short
    where it would touch an obstacle or a teammate, a disc that touches a teammate sliding
    along it for the rest (see the module notes).

    Parameters
    ----------
    before, after : numpy.ndarray
        ``(n, 3)`` poses before the step and as the dynamics left them.
    radii : numpy.ndarray
        ``(n,)`` robot radii (m); 0 everywhere: robots pass through each other.
    obstacles : sequence of numpy.ndarray
        Polygons (:func:`polygon`).
    """
    out = np.array(after, dtype=float)
    radii = np.asarray(radii, dtype=float)
    discs = bool(np.any(radii > 0))
    placed = np.array(before[:, :2], dtype=float)
    for i in range(out.shape[0]):
        start, end = before[i, :2], out[i, :2]
        point = _cut(i, start, end, placed, radii, obstacles, discs)
        if discs and not np.allclose(point, end):  # slide along the teammate it touches
            point = _cut(i, point, _slide(i, point, end, placed, radii), placed, radii,
                         obstacles, discs)  # fmt: skip
        out[i, :2] = point
        placed[i] = out[i, :2]
    return out
