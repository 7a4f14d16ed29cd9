"""Active-inference levels ``"first"``, ``"second"`` and ``"third"`` in the simulator.

Each robot runs :class:`epistemica.aif.Controller` at its order over the valid
configurations of the goals it knows of; multitask robots first select the tasks the team
works on now (:mod:`~epistemica.sim.tasking`) and reason over allocations of those. The
control grid respects the robot's limits: four speeds up to its ``max_speed`` and headings
changes that include "straight ahead" (the full turn when allowed, else nine values in
``[-max_turn, max_turn]``).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from epistemica.aif.configurations import valid_configurations
from epistemica.aif.controller import Controller
from epistemica.aif.information import entropy
from epistemica.aif.motion import DEFAULT_HEADING_CHANGES, control_grid
from epistemica.sim.baselines import open_goals
from epistemica.sim.policy import Decisions, Policy
from epistemica.sim.sensing import Observations
from epistemica.sim.tasking import select_tasks, task_slots

__all__ = ["LEVELS", "ActiveInference"]

#: Order of reasoning of each active-inference level.
LEVELS = {"first": 1, "second": 2, "third": 3}


def _grid(max_speed: float, max_turn: float) -> np.ndarray:
    speeds = max_speed * np.array([0.0, 1 / 3, 2 / 3, 1.0])
    if max_turn >= np.pi:
        changes = DEFAULT_HEADING_CHANGES
    else:
        changes = np.linspace(-max_turn, max_turn, 9)
    return control_grid(speeds, changes)


@lru_cache(maxsize=32)
def _allocations(n: int, m: int) -> np.ndarray:
    # Read-only: shared by every controller over an n-robot, m-slot subset.
    rows = valid_configurations("allocation", n, m)
    rows.setflags(write=False)
    return rows


class ActiveInference(Policy):
    """Expected-free-energy control at a given order of reasoning.

    Parameters
    ----------
    order : {1, 2, 3}
        Order of reasoning.
    **options
        Passed to :class:`epistemica.aif.Controller` (weights, horizon, ...).
    """

    def __init__(self, order: int, **options) -> None:
        self.order = int(order)
        self.options = options
        self.name = {v: k for k, v in LEVELS.items()}.get(self.order, f"order-{order}")

    def start(self, scenario, robots, generators) -> None:
        super().start(scenario, robots, generators)
        self._controllers: dict[tuple, Controller] = {}

    def _controller(self, robot: int, goals: np.ndarray, configurations) -> Controller:
        s = self.scenario
        key = (float(s.max_speed[robot]), float(s.max_turn[robot]), goals.tobytes())
        ctrl = self._controllers.get(key)
        if ctrl is None:
            grid = _grid(s.max_speed[robot], s.max_turn[robot])
            ctrl = Controller(
                s.goals[goals],
                s.sensors,
                configurations(),
                order=self.order,
                controls=grid,
                dt=s.dt,
                **self.options,
            )
            if len(self._controllers) > 64:  # multitask subsets change: bound the cache
                self._controllers.clear()
            self._controllers[key] = ctrl
        return ctrl

    def _configurations(self, observations: Observations, robot: int):
        """Goal indices the robot reasons over, and a builder of their configurations."""
        s, n = self.scenario, self.scenario.n_robots
        known = open_goals(s, observations, robot)
        if s.mission == "multitask":
            slots = task_slots(select_tasks(observations.poses[robot], s.goals, known), n)
            return slots, lambda: _allocations(n, len(slots))
        if known.size == s.n_goals:
            return known, s.configurations
        rows = s.configurations()
        usable = np.isin(rows, known).all(axis=1)
        if not usable.any():  # too few goals known for any valid configuration
            return known[:0], None
        remap = np.full(s.n_goals, -1)
        remap[known] = np.arange(known.size)
        return known, lambda: remap[rows[usable]]

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        n = self.scenario.n_robots
        out = Decisions.of(np.zeros((len(robots), 2)), np.full((len(robots), n), -1))
        for row, robot in enumerate(robots):
            goals, configurations = self._configurations(observations, robot)
            if goals.size == 0:
                continue  # stays put: nothing known to go to
            ctrl = self._controller(robot, goals, configurations)
            d = ctrl.decide(robot, observations.poses[robot])
            out.controls[row] = d.control
            out.focal[row] = goals[ctrl.configurations[d.focal]]
            out.entropy[row] = entropy(d.belief)
            out.considered[row] = ctrl.configurations.shape[0]
        return out
