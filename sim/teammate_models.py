"""Each robot's online models of its teammates (issue 19 §2), for the active levels.

Every step a robot scores each teammate's observed move under the behaviour library of
:mod:`epistemica.aif.teammates` (the team's own level, greedy, the other convention,
stationary), updates its posterior over them, and turns the team prior it was handed into
the type mixture: the belief it infers from then weights each configuration by
``Σ_t P(t) P_t(teammate's goal)`` (:func:`~epistemica.aif.teammates.mix_configurations`).
Only teammates seen at both steps are scored and mixed; the rest keep the team's model.

Examples
--------
>>> from epistemica.sim import Scenario
>>> s = Scenario("rendezvous", [[0, 0, 0], [20, 0, 0]], [[2, 0], [18, 0]], ["range"] * 2)
>>> models = TeammateModels(s, sigma=1.0, leak=0.02)
>>> models.posterior(0).round(3).tolist()   # nothing observed yet: the type prior
[[0.5, 0.167, 0.167, 0.167], [0.5, 0.167, 0.167, 0.167]]
"""

from __future__ import annotations

import numpy as np

from epistemica.aif.teammates import (
    TYPE_PRIOR,
    least_cost_row,
    mix_configurations,
    motion_log_likelihood,
    type_goal_probabilities,
    update_types,
)

__all__ = ["TeammateModels"]


class TeammateModels:
    """The type posteriors each robot keeps of its teammates, and the mixture they give.

    Parameters
    ----------
    scenario : Scenario
        The trial's scenario (goals, speeds, observation noise).
    sigma : float
        Metres of motion-model error on top of the observation noise: a step is scored with
        variance ``sigma² + 2 · position_noise`` per axis.
    leak : float
        Rate at which each posterior is mixed back with the type prior every step.
    """

    def __init__(self, scenario, sigma: float, leak: float) -> None:
        self.scenario = scenario
        n = scenario.n_robots
        self.sigma = float(np.sqrt(sigma**2 + 2 * scenario.position_noise))
        self.leak = float(leak)
        self._log_types = np.tile(np.log(TYPE_PRIOR), (n, n, 1))  # observer, teammate, T
        # observer -> (step, positions seen, seen mask, goal indices, (n, T, m) predictions)
        self._last: dict[int, tuple] = {}

    def posterior(self, observer: int) -> np.ndarray:
        """``(n, T)`` the observer's posterior over each robot's type (its own row unused)."""
        return np.exp(self._log_types[observer])

    def mix(self, observer: int, observations, goals: np.ndarray, configurations, prior,
            apply: bool = True):  # fmt: skip
        """The observer's prior over ``configurations`` (of goal indices ``goals``) made the
        type mixture, after scoring this step's moves; ``None`` (uniform) is accepted.
        With ``apply`` false the moves are scored but the prior is returned as it is."""
        s, step = self.scenario, observations.step
        k = configurations.shape[0]
        prior = np.full(k, 1.0 / k) if prior is None else np.asarray(prior, dtype=float)
        positions = observations.poses[observer][:, :2]
        seen = observations.seen[observer].copy()
        seen[observer] = False
        where = s.goals[goals]
        last = self._last.get(observer)
        if last is not None and last[0] == step - 1 and np.array_equal(last[3], goals):
            scored = seen & last[2]
            if scored.any():
                reach = s.max_speed[scored] * s.dt
                ll = motion_log_likelihood(
                    last[1][scored], positions[scored], last[4][scored], where, reach, self.sigma
                )
                types = self._log_types[observer]
                types[scored] = update_types(types[scored], ll, self.leak)
        marginal = np.stack(
            [
                np.bincount(configurations[:, j], weights=prior, minlength=goals.size)
                for j in range(configurations.shape[1])
            ]
        )
        convention = least_cost_row(positions, where, configurations)
        predictions = type_goal_probabilities(marginal, positions, where, convention)
        self._last[observer] = (step, positions.copy(), seen, goals.copy(), predictions)
        if not apply:
            return prior
        return mix_configurations(
            prior, self._log_types[observer], predictions, configurations, np.flatnonzero(seen)
        )
