"""Evidence that a robot is heading for a goal, by sensor and by order of reasoning.

Robot ``i`` turns positions (its own exact pose, the others as it observes them) into an
evidence array ``e[r, g]`` in ``(0, 1]`` for every robot ``r`` and goal ``g`` (the paper's
salience ``exp(-h / eta)``):

- range sensing: ``h`` is the distance from ``r`` to ``g`` (``eta`` in metres, 50 m in the
  paper protocol);
- bearing sensing from a viewpoint ``v``: ``h`` is the angle, seen from ``v``, between
  robot ``r`` and goal ``g`` (``eta_bearing`` in radians). Where the angle is undefined
  (``r`` or ``g`` on top of ``v``, ``atan2(0, 0)``) the measurement is neutral: ``pi / 2``.

Sensor dominance ``range ≻ bearing``: positions determine every angle, so a range robot
can reconstruct what a bearing robot measures, not the reverse; equal sensors reconstruct
each other. Perspective chains follow from it:

- order 0: ``i`` about itself (own pose, so distances, whatever the sensor);
- order 1: chain ``(i,)``: the others as ``i`` measures them;
- order 2: chains ``(i, j)``, ``j != i`` with ``ω_i ⪰ ω_j``: what ``j`` measures of every
  robot but itself (including ``i``), computed from ``i``'s observations;
- order 3: chains ``(i, j, k)`` with ``(i, j)`` an order-2 chain, ``k ∉ {i, j}`` and
  ``ω_j ⪰ ω_k``: what ``j`` would reconstruct of ``k``'s measurements. The nested
  dominance test is ``j``'s, not ``i``'s: a range ``i`` reaches a range ``k`` at order 2,
  but not through a bearing ``j`` at order 3.

The evidence of order ``k`` is the sum over the order-``k`` chains of the last robot's
measurements (the paper's ``h^(k) = sum_{a in R_i^k}``), and the per-robot goal
distribution is ``softmax(sum_k e^(k))`` (:func:`epistemica.aif.likelihood.goal_log_probabilities`).

Examples
--------
>>> goals = [[10.0, 0.0], [0.0, 10.0]]
>>> positions = [[0.0, 0.0], [9.0, 0.0]]
>>> range_evidence(positions, goals, eta=10.0).round(3).tolist()
[[0.368, 0.368], [0.905, 0.26]]
>>> perspective_sets(["range", "bearing", "range"], 0, 3)
[[(0,)], [(0,)], [(0, 1), (0, 2)], [(0, 2, 1)]]
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from epistemica.aif._validate import as_finite, positive
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "BEARING",
    "DEFAULT_ETA",
    "DEFAULT_ETA_BEARING",
    "RANGE",
    "SENSORS",
    "bearing_evidence",
    "chain_counts",
    "dominates",
    "evidence_by_order",
    "measurement_stack",
    "measurements",
    "perspective_sets",
    "range_evidence",
]

RANGE = "range"
BEARING = "bearing"
#: Sensor types, from the most to the least informative.
SENSORS = (RANGE, BEARING)
_RANK = {RANGE: 1, BEARING: 0}
#: Evidence length scale of range sensing (metres), as in the paper protocol.
DEFAULT_ETA = 50.0
#: Evidence angle scale of bearing sensing (radians).
DEFAULT_ETA_BEARING = 1.0
# Points closer than this (relative to the scene size) count as coincident.
_COINCIDENT = 1e-9


def check_sensors(sensors, n: int | None = None) -> tuple[str, ...]:
    """The sensor types as a tuple, each checked (and ``n`` of them, when given)."""
    if isinstance(sensors, str):
        sensors = [sensors]
    out = tuple(sensors)
    for s in out:
        if s not in _RANK:
            raise InvalidArgumentError(
                f"unknown sensor {s!r}", hint=f"use one of {', '.join(map(repr, SENSORS))}"
            )
    if n is not None and len(out) != n:
        raise InvalidArgumentError(
            f"got {len(out)} sensors for {n} robots", hint="give one sensor type per robot"
        )
    return out


def _points(value, name: str, n: int | None = None) -> np.ndarray:
    pts = as_finite(value, name, ndim=2, shape=(n, None))
    if pts.shape[1] < 2:
        raise InvalidArgumentError(
            f"{name} must have x and y columns, got shape {pts.shape}",
            hint="pass an (n, 2) array of positions, or (n, 3) poses x, y, heading",
        )
    if pts.shape[0] == 0:
        raise InvalidArgumentError(f"{name} is empty", hint="pass at least one point")
    return pts[:, :2]


def dominates(sensor_a: str, sensor_b: str) -> bool:
    """True when a robot with ``sensor_a`` can reconstruct ``sensor_b``'s measurements.

    Examples
    --------
    >>> dominates("range", "bearing"), dominates("bearing", "range")
    (True, False)
    """
    a, b = check_sensors([sensor_a, sensor_b])
    return _RANK[a] >= _RANK[b]


def range_evidence(positions, goals, eta: float = DEFAULT_ETA) -> np.ndarray:
    """``exp(-d(r, g) / eta)`` for every robot ``r`` and goal ``g``, shape ``(n, m)``.

    Examples
    --------
    >>> range_evidence([[0.0, 0.0]], [[0.0, 0.0], [1e6, 0.0]]).tolist()
    [[1.0, 0.0]]
    """
    pos = _points(positions, "positions")
    gl = _points(goals, "goals")
    eta = positive(eta, "eta")
    d = np.hypot(pos[:, None, 0] - gl[None, :, 0], pos[:, None, 1] - gl[None, :, 1])
    return np.exp(-d / eta)


def bearing_evidence(
    viewpoint, positions, goals, eta_bearing: float = DEFAULT_ETA_BEARING
) -> np.ndarray:
    """``exp(-angle / eta_bearing)``: angle at ``viewpoint`` between robot ``r`` and goal ``g``.

    Examples
    --------
    Seen from the origin, a robot on the x axis is aligned with a goal on the x axis:

    >>> bearing_evidence([0.0, 0.0], [[5.0, 0.0]], [[9.0, 0.0], [0.0, 9.0]]).round(3).tolist()
    [[1.0, 0.208]]
    """
    v = as_finite(viewpoint, "viewpoint", ndim=1)[:2]
    pos = _points(positions, "positions")
    gl = _points(goals, "goals")
    eta_bearing = positive(eta_bearing, "eta_bearing")
    return np.exp(-_angles(v, pos, gl) / eta_bearing)


def _angles(v: np.ndarray, pos: np.ndarray, gl: np.ndarray) -> np.ndarray:
    return angle_batch(v, pos, gl, _scale(pos, gl, v))


def _scale(*arrays) -> float:
    return max(1.0, max(float(np.abs(a).max()) for a in arrays))


def angle_batch(v: np.ndarray, pos: np.ndarray, gl: np.ndarray, scale: float) -> np.ndarray:
    """Angles at viewpoints ``v (..., 2)`` between points ``pos (..., n, 2)`` and goals."""
    dr = pos - v[..., None, :]
    dg = gl - v[..., None, :]
    r_here = np.hypot(dr[..., 0], dr[..., 1]) <= _COINCIDENT * scale
    g_here = np.hypot(dg[..., 0], dg[..., 1]) <= _COINCIDENT * scale
    # Angle between the two directions via atan2(|cross|, dot): exact near 0 and pi.
    cross = dr[..., :, None, 0] * dg[..., None, :, 1] - dr[..., :, None, 1] * dg[..., None, :, 0]
    dot = dr[..., :, None, 0] * dg[..., None, :, 0] + dr[..., :, None, 1] * dg[..., None, :, 1]
    angle = np.arctan2(np.abs(cross), dot)
    # Undefined directions (atan2(0, 0)) carry no information: a neutral right angle.
    angle = np.where(r_here[..., :, None] | g_here[..., None, :], np.pi / 2, angle)
    return angle


def stack_evidence(
    pos: np.ndarray,
    gl: np.ndarray,
    bearing: np.ndarray,
    eta: float,
    eta_bearing: float,
    scale=None,
):
    """Unchecked core of :func:`measurement_stack`; also returns the range evidence.

    ``scale`` (default: of the whole batch) sets the coincidence tolerance; a ``(b, 1, 1)``
    array gives each scene its own, so that a batch of several robots' scenes is
    measured exactly as each robot's batch alone.
    """
    n = pos.shape[1]
    d = np.hypot(pos[..., :, None, 0] - gl[:, 0], pos[..., :, None, 1] - gl[:, 1])
    ranged = np.exp(-d / eta)
    out = np.empty((pos.shape[0], n, n, gl.shape[0]))
    out[:, ~bearing] = ranged[:, None]
    if bearing.any():
        scale = _scale(pos, gl) if scale is None else scale
        ang = angle_batch(pos[:, bearing], pos[:, None], gl, scale)
        out[:, bearing] = np.exp(-ang / eta_bearing)
    out[:, np.arange(n), np.arange(n)] = 0.0
    return out, ranged


def measurement_stack(
    positions,
    goals,
    sensors: Sequence[str],
    eta: float = DEFAULT_ETA,
    eta_bearing: float = DEFAULT_ETA_BEARING,
) -> np.ndarray:
    """Every robot's measurements of every robot, for a batch of scenes.

    ``positions`` is ``(n, 2)`` or a batch ``(b, n, 2)``; the result has shape
    ``(b, n, n, m)`` (or ``(n, n, m)``): ``[.., v, r, g]`` is what viewpoint ``v`` measures
    of robot ``r`` about goal ``g`` (zero on ``r == v``), as :func:`measurements`.

    Examples
    --------
    >>> stack = measurement_stack([[0, 0], [9, 0]], [[10, 0], [0, 10]], ["range", "bearing"])
    >>> stack.shape
    (2, 2, 2)
    >>> bool(np.allclose(stack[1], measurements(1, [[0, 0], [9, 0]], [[10, 0], [0, 10]],
    ...                                         ["range", "bearing"])))
    True
    """
    pos = as_finite(positions, "positions")
    single = pos.ndim == 2
    if single:
        pos = pos[None]
    if pos.ndim != 3 or pos.shape[2] < 2:
        raise InvalidArgumentError(
            f"positions must be (n, 2) or (b, n, 2), got shape {pos.shape}",
            hint="one row of x, y per robot",
        )
    pos = pos[..., :2]
    n = pos.shape[1]
    bearing = np.array([s == BEARING for s in check_sensors(sensors, n)])
    gl = _points(goals, "goals")
    out, _ = stack_evidence(
        pos, gl, bearing, positive(eta, "eta"), positive(eta_bearing, "eta_bearing")
    )
    return out[0] if single else out


def measurements(
    viewpoint: int,
    positions,
    goals,
    sensors: Sequence[str],
    eta: float = DEFAULT_ETA,
    eta_bearing: float = DEFAULT_ETA_BEARING,
) -> np.ndarray:
    """What robot ``viewpoint`` measures of every other robot, shape ``(n, m)``.

    The viewpoint's own row is zero: a robot's measurements of the others say nothing
    about its own goal (its own pose enters at order 0 only).

    Examples
    --------
    >>> measurements(0, [[0, 0], [9, 0]], [[10, 0], [0, 10]], ["range", "range"], eta=10.0
    ...              ).round(3).tolist()
    [[0.0, 0.0], [0.905, 0.26]]
    """
    pos = _points(positions, "positions")
    sensors = check_sensors(sensors, pos.shape[0])
    if sensors[viewpoint] == RANGE:
        out = range_evidence(pos, goals, eta)
    else:
        out = bearing_evidence(pos[viewpoint], pos, goals, eta_bearing)
    out[viewpoint] = 0.0
    return out


def noise_attenuation(
    pos: np.ndarray,
    robots: np.ndarray,
    bearing: np.ndarray,
    position_noise: float,
    eta: float,
    eta_bearing: float,
) -> np.ndarray:
    """``(R, n)`` per-row factors ``1 / sqrt(1 + pi s² / 8)`` for noisy observed positions,
    each robot ``robots[r]`` in its own view ``pos[r]`` (``(R, n, 2)``).

    A row's evidence differs between goals by about ``Δd / eta`` (range) or
    ``Δangle / eta_bearing`` (bearing, seen from the deciding robot); noise of variance
    ``σ²`` per axis gives those differences a variance ``s² ≈ 2σ² / eta²`` or
    ``2σ² / (eta_bearing · ρ)²`` at range ``ρ`` (docs/aif.md, "Observation noise"). The
    deciding robot's own row is exact.

    Examples
    --------
    >>> pos = np.array([[[0.0, 0.0], [10.0, 0.0]]])
    >>> noise_attenuation(pos, np.array([0]), np.array([False, False]), 0.0, 50.0, 1.0)
    array([[1., 1.]])
    """
    R = robots.size
    rel = pos - pos[np.arange(R), robots][:, None]
    rho = np.maximum(np.hypot(rel[..., 0], rel[..., 1]), 1.0)
    s2 = np.where(
        bearing[robots][:, None],
        2.0 * position_noise / (eta_bearing * rho) ** 2,
        2.0 * position_noise / eta**2,
    )
    factor = 1.0 / np.sqrt(1.0 + np.pi * s2 / 8.0)
    factor[np.arange(R), robots] = 1.0
    return factor


def check_robot(robot, n: int) -> int:
    """``robot`` as an index in ``range(n)``, or a clear error."""
    if isinstance(robot, bool) or not isinstance(robot, (int, np.integer)) or not 0 <= robot < n:
        raise InvalidArgumentError(
            f"robot must be an index in range({n}), got {robot!r}",
            hint="robots are numbered from 0 in the order of the positions array",
        )
    return int(robot)


def check_order(order) -> int:
    """``order`` as an order of reasoning 0-3, or a clear error."""
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or not 0 <= order <= 3:
        raise InvalidArgumentError(
            f"order must be 0, 1, 2 or 3, got {order!r}",
            hint="0: self only; 1: the others as I see them; 2: as j sees them; 3: as j "
            "thinks k sees them",
        )
    return int(order)


def perspective_sets(sensors: Sequence[str], robot: int, order: int) -> list[list[tuple]]:
    """The chains ``R_i^k`` for ``k = 0 .. order``, each a tuple of robot indices.

    Examples
    --------
    A bearing robot cannot take a range robot's perspective:

    >>> perspective_sets(["bearing", "range", "bearing"], 0, 2)
    [[(0,)], [(0,)], [(0, 2)]]
    """
    sensors = check_sensors(sensors)
    n = len(sensors)
    robot = check_robot(robot, n)
    order = check_order(order)
    levels: list[list[tuple]] = [[(robot,)]]
    if order >= 1:
        levels.append([(robot,)])
    for _ in range(2, order + 1):
        nxt = []
        for chain in levels[-1]:
            last = chain[-1]
            for k in range(n):
                if k in chain or not dominates(sensors[last], sensors[k]):
                    continue
                nxt.append((*chain, k))
        levels.append(nxt)
    return levels


def chain_counts(sensors: Sequence[str], robot: int, order: int) -> np.ndarray:
    """How many chains of each order end at each robot, shape ``(order + 1, n)``.

    Row 0 marks the robot itself (order 0). Evidence of order ``k`` is
    ``sum_v counts[k, v] * measurements(v)``.

    Examples
    --------
    >>> chain_counts(["range", "range", "range"], 0, 3).tolist()
    [[1, 0, 0], [1, 0, 0], [0, 1, 1], [0, 1, 1]]
    """
    levels = perspective_sets(sensors, robot, order)
    counts = np.zeros((len(levels), len(check_sensors(sensors))), dtype=np.int64)
    for k, chains in enumerate(levels):
        for chain in chains:
            counts[k, chain[-1]] += 1
    return counts


def evidence_by_order(
    robot: int,
    positions,
    goals,
    sensors: Sequence[str],
    order: int,
    eta: float = DEFAULT_ETA,
    eta_bearing: float = DEFAULT_ETA_BEARING,
) -> np.ndarray:
    """Evidence of each order from ``robot``'s perspective, shape ``(order + 1, n, m)``.

    Parameters
    ----------
    robot : int
        The reasoning robot ``i``.
    positions : array_like
        ``(n, 2)`` positions (or ``(n, 3)`` poses) as robot ``i`` observes them.
    goals : array_like
        ``(m, 2)`` goal positions.
    sensors : sequence of {"range", "bearing"}
        One sensor type per robot.
    order : {0, 1, 2, 3}
        Deepest order of reasoning.
    eta, eta_bearing : float
        Length scale (m) of range evidence and angle scale (rad) of bearing evidence.

    Examples
    --------
    >>> e = evidence_by_order(0, [[0, 0], [9, 0]], [[10, 0], [0, 10]], ["range"] * 2, 2,
    ...                       eta=10.0)
    >>> e.sum(axis=0).round(3).tolist()  # own distance + 1's view of me; my view of 1
    [[0.736, 0.736], [0.905, 0.26]]
    >>> e[2].round(3).tolist()
    [[0.368, 0.368], [0.0, 0.0]]
    """
    pos = _points(positions, "positions")
    n = pos.shape[0]
    sensors = check_sensors(sensors, n)
    robot = check_robot(robot, n)
    counts = chain_counts(sensors, robot, order)
    gl = _points(goals, "goals")
    out = np.zeros((counts.shape[0], n, gl.shape[0]))
    out[0, robot] = range_evidence(pos[robot : robot + 1], gl, eta)[0]
    cache: dict[int, np.ndarray] = {}
    for k in range(1, counts.shape[0]):
        for v in np.flatnonzero(counts[k]):
            if v not in cache:
                cache[v] = measurements(int(v), pos, gl, sensors, eta, eta_bearing)
            out[k] += counts[k, v] * cache[v]
    return out
