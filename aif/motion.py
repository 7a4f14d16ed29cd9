"""Candidate controls and the poses they lead to.

A control is a ``(speed, heading change)`` pair. The dynamics are "turn first, then move
``v·dt`` along the new heading"; headings are wrapped to ``(-pi, pi]``. The default grid is
the paper protocol's four speeds times eight heading changes evenly spaced over the full
turn, which contains "straight ahead" (change 0) and "stop" (speed 0).

Examples
--------
>>> grid = control_grid(speeds=(0.0, 1.0), heading_changes=(0.0, np.pi / 2))
>>> grid.tolist()
[[0.0, 0.0], [0.0, 1.5707963267948966], [1.0, 0.0], [1.0, 1.5707963267948966]]
>>> predict_poses([0.0, 0.0, 0.0], grid).round(6).tolist()
[[0.0, 0.0, 0.0], [0.0, 0.0, 1.570796], [1.0, 0.0, 0.0], [0.0, 1.0, 1.570796]]
"""

from __future__ import annotations

import numpy as np

from epistemica.aif._validate import as_finite, positive
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "DEFAULT_HEADING_CHANGES",
    "DEFAULT_SPEEDS",
    "control_grid",
    "move",
    "predict_poses",
    "wrap_angle",
]

#: Speeds (m/s) of the paper protocol; 0 is "stop".
DEFAULT_SPEEDS = (0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0)
#: Eight heading changes evenly spaced over the full turn, including 0 ("straight ahead").
DEFAULT_HEADING_CHANGES = tuple(np.linspace(-np.pi, np.pi, 8, endpoint=False))


def control_grid(speeds=DEFAULT_SPEEDS, heading_changes=DEFAULT_HEADING_CHANGES) -> np.ndarray:
    """All ``(speed, heading change)`` pairs, shape ``(len(speeds) * len(changes), 2)``.

    Parameters
    ----------
    speeds : array_like
        Non-negative speeds (m/s), slowest axis of the grid.
    heading_changes : array_like
        Heading changes (rad) applied before moving.

    Examples
    --------
    >>> grid = control_grid()
    >>> grid.shape
    (32, 2)
    >>> bool(((grid[:, 0] == 0) & (grid[:, 1] == 0)).any())  # stop
    True
    >>> bool(((grid[:, 0] == 1) & (grid[:, 1] == 0)).any())  # straight ahead
    True
    """
    v = as_finite(speeds, "speeds", ndim=1)
    dh = as_finite(heading_changes, "heading_changes", ndim=1)
    if v.size == 0 or dh.size == 0 or np.any(v < 0):
        raise InvalidArgumentError(
            "speeds must be non-empty and >= 0, heading_changes non-empty",
            hint="e.g. speeds=(0, 0.5, 1), heading_changes=(-0.5, 0, 0.5)",
        )
    vv, hh = np.meshgrid(v, dh, indexing="ij")
    return np.column_stack([vv.ravel(), hh.ravel()])


def predict_poses(pose, controls, dt: float = 1.0) -> np.ndarray:
    """Poses ``(x, y, heading)`` after each control: turn first, then move ``v·dt``.

    Parameters
    ----------
    pose : array_like
        ``(..., 3)`` current pose(s); leading axes are kept.
    controls : array_like
        ``(c, 2)`` ``(speed, heading change)`` rows.
    dt : float
        Time step (s).

    Returns
    -------
    numpy.ndarray
        Shape ``(..., c, 3)``.

    Examples
    --------
    >>> predict_poses([0.0, 0.0, 0.0], [[1.0, 0.0], [0.0, np.pi / 2]]).round(6).tolist()
    [[1.0, 0.0, 0.0], [0.0, 0.0, 1.570796]]
    """
    p = as_finite(pose, "pose")
    u = as_finite(controls, "controls", ndim=2, shape=(None, 2))
    dt = positive(dt, "dt")
    if p.ndim == 0 or p.shape[-1] != 3:
        raise InvalidArgumentError(
            f"pose must end in (x, y, heading), got shape {p.shape}", hint="pass three numbers"
        )
    return turn_then_move(p[..., None, :], u, dt)


def move(poses, controls, dt: float = 1.0) -> np.ndarray:
    """Each robot's next pose under its own control: turn first, then move ``v·dt``.

    The same dynamics as :func:`predict_poses`, one control per robot instead of every
    control for one pose; the simulator steps the world with it.

    Parameters
    ----------
    poses : array_like
        ``(n, 3)`` poses ``x, y, heading``.
    controls : array_like
        ``(n, 2)`` ``(speed, heading change)``, row ``i`` for robot ``i``.
    dt : float
        Time step (s).

    Examples
    --------
    >>> move([[0.0, 0.0, 0.0], [1.0, 1.0, np.pi]], [[1.0, np.pi / 2], [2.0, 0.0]]).round(6)
    array([[ 0.      ,  1.      ,  1.570796],
           [-1.      ,  1.      ,  3.141593]])
    """
    p = as_finite(poses, "poses", ndim=2, shape=(None, 3))
    u = as_finite(controls, "controls", ndim=2, shape=(p.shape[0], 2))
    return turn_then_move(p, u, positive(dt, "dt"))


def wrap_angle(angle) -> np.ndarray:
    """Angles wrapped to ``(-pi, pi]``.

    Examples
    --------
    >>> wrap_angle([np.pi, -np.pi, 3 * np.pi / 2]).round(6).tolist()
    [3.141593, 3.141593, -1.570796]
    """
    a = np.asarray(angle, dtype=float)
    return np.pi - np.mod(np.pi - a, 2.0 * np.pi)


def turn_then_move(p: np.ndarray, u: np.ndarray, dt: float) -> np.ndarray:
    # p (..., 3) broadcasts against u (..., 2): the one implementation of the dynamics.
    heading = wrap_angle(p[..., 2] + u[..., 1])
    x = p[..., 0] + u[..., 0] * dt * np.cos(heading)
    y = p[..., 1] + u[..., 0] * dt * np.sin(heading)
    return np.stack([x, y, heading], axis=-1)
