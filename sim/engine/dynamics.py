"""How robots move and how they sense: the :class:`Dynamics` and :class:`Sensor` protocols.

A :class:`~epistemica.sim.Scenario` takes one of each (``dynamics=`` and ``observation=``);
the simulator calls them every step and nothing else about motion or measurement is fixed.
The built-in implementations are :class:`Unicycle` (turn first, then move ``v·dt``: the
paper's robots, the default), and the two observation models :class:`PaperSensor`
(``"paper"``: noisy positions) and :class:`HonestSensor` (``"honest"``: what a range or a
bearing sensor gives). Contacts (disc robots, obstacles) are applied after the dynamics by
:mod:`epistemica.sim.engine.obstacles`, so any dynamics gets them.

A robot of your own is any object with a ``step(poses, controls, dt)`` method; a sensor any
object with ``name`` and ``measure(poses, estimates, noise, scenario)``. They must be
deterministic given their arguments: every random draw comes from the noise the simulator
passes in, so one seed gives the same trial for every reasoning level.

Examples
--------
A robot that slides sideways as well as forward (holonomic), plugged into a scenario:

>>> from epistemica.sim import Scenario, simulate
>>> class Sideways:
...     def step(self, poses, controls, dt):
...         out = Unicycle().step(poses, controls, dt)
...         out[:, 1] += 0.1 * dt
...         return out
>>> s = Scenario("rendezvous", [[0, 0], [4, 0]], [[2, 5]], ["range"] * 2, dynamics=Sideways())
>>> simulate(s, "zero", seed=0).success
True
>>> isinstance(Unicycle(), Dynamics), isinstance(PaperSensor(), Sensor)
(True, True)
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np

from epistemica.aif.motion import move

__all__ = ["SENSOR_MODELS", "Dynamics", "HonestSensor", "PaperSensor", "Sensor", "Unicycle"]


@runtime_checkable
class Dynamics(Protocol):
    """Motion of the team over one step.

    ``step(poses, controls, dt)`` takes the ``(n, 3)`` poses ``x, y, heading``, the
    ``(n, 2)`` controls ``(speed, heading change)`` already clipped to each robot's
    limits, and the time step; it returns the ``(n, 3)`` poses after the step (a new
    array). Process noise, the workspace bound and contacts are applied afterwards by the
    simulator.
    """

    def step(self, poses: np.ndarray, controls: np.ndarray, dt: float) -> np.ndarray: ...


@runtime_checkable
class Sensor(Protocol):
    """What each robot measures of every other robot.

    ``measure(poses, estimates, noise, scenario)`` takes the true ``(n, 3)`` poses, the
    previous ``(n, n, 3)`` estimates (row ``i``: where robot ``i`` placed everyone), the
    step's ``(n, n, 2)`` standard normal draws (row ``i`` from robot ``i``'s own stream)
    and the scenario; it returns ``(n, n, 3)`` measured poses. The simulator keeps a
    measurement only where robot ``j`` is visible to robot ``i`` and sets each robot's own
    pose exactly. An optional ``variance(distance, scenario)``, the per-axis variance of a
    sighting at that distance, lets the planner weigh sightings (``plan_noise``); without
    it ``position_noise`` is assumed.
    """

    name: str

    def measure(
        self, poses: np.ndarray, estimates: np.ndarray, noise: np.ndarray, scenario: Any
    ) -> np.ndarray: ...


class Unicycle:
    """Turn first (by the heading change), then move ``speed · dt`` along the new heading.

    Examples
    --------
    >>> Unicycle().step(np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, np.pi / 2]]), 1.0).round(6)
    array([[0.      , 1.      , 1.570796]])
    """

    name = "unicycle"

    def step(self, poses: np.ndarray, controls: np.ndarray, dt: float) -> np.ndarray:
        return move(poses, controls, dt)

    def __repr__(self) -> str:
        return "Unicycle()"


def _everyone(poses: np.ndarray) -> np.ndarray:
    """``(n, n, 3)``: row ``i`` is every robot's true pose."""
    return np.broadcast_to(poses, (poses.shape[0], *poses.shape)).copy()


class PaperSensor:
    """Every teammate's position plus ``N(0, position_noise)`` per axis (its heading exact).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> poses, noise = np.zeros((2, 3)), np.ones((2, 2, 2))
    >>> PaperSensor().measure(poses, None, noise, SimpleNamespace(position_noise=4.0))[0, 1]
    array([2., 2., 0.])
    """

    name = "paper"

    def measure(self, poses, estimates, noise, scenario) -> np.ndarray:
        truth = _everyone(poses)
        truth[..., :2] += np.sqrt(scenario.position_noise) * noise
        return truth

    def variance(self, distance: np.ndarray, scenario) -> np.ndarray:
        """Per-axis variance (m²) of a sighting at ``distance``: ``position_noise``."""
        return np.full(np.shape(distance), float(scenario.position_noise))

    def __repr__(self) -> str:
        return "PaperSensor()"


class HonestSensor:
    """What each robot's own sensor gives: a range robot measures range
    (``N(0, position_noise)``) and bearing (``N(0, angle_noise)``); a bearing robot the
    bearing only, keeping along the new ray the range of its previous estimate (a quarter
    of the workspace until anything better is known). Headings of others are not measured.
    """

    name = "honest"

    def measure(self, poses, estimates, noise, scenario) -> np.ndarray:
        s = scenario
        truth = _everyone(poses)
        own = poses[:, None, :2]
        rel = truth[..., :2] - own
        angle = np.arctan2(rel[..., 1], rel[..., 0]) + np.sqrt(s.angle_noise) * noise[..., 1]
        measured_range = (
            np.hypot(rel[..., 0], rel[..., 1]) + np.sqrt(s.position_noise) * noise[..., 0]
        )
        remembered = np.hypot(*(estimates[..., :2] - own).transpose(2, 0, 1))
        guess = np.where(remembered > 1e-9, remembered, s.workspace / 4)
        bearing = np.array([sensor == "bearing" for sensor in s.sensors])
        r = np.where(bearing[:, None], guess, np.abs(measured_range))
        truth[..., 0] = own[..., 0] + r * np.cos(angle)
        truth[..., 1] = own[..., 1] + r * np.sin(angle)
        truth[..., 2] = 0.0
        return truth

    def variance(self, distance: np.ndarray, scenario) -> np.ndarray:
        """Per-axis variance (m²) of a range robot's sighting at ``distance``: the mean of
        its error ellipse's axes, the range's ``position_noise`` and the bearing's
        ``distance² angle_noise``."""
        distance = np.asarray(distance, dtype=float)
        return (scenario.position_noise + distance**2 * scenario.angle_noise) / 2

    def __repr__(self) -> str:
        return "HonestSensor()"


#: The observation models a scenario (or a mission's ``sensing model``) names.
SENSOR_MODELS: dict[str, Sensor] = {"paper": PaperSensor(), "honest": HonestSensor()}
