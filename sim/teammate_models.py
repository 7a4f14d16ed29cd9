"""Each robot's online models of its teammates (issue 19 §2), for the active levels.

Every step a robot scores each teammate's observed move under the behaviour library of
:mod:`epistemica.aif.teammates` (the team's own level, greedy, the other convention,
stationary), updates its posterior over them, and turns the team prior it was handed into
the type mixture (:func:`~epistemica.aif.teammates.mix_configurations`, docs/aif.md §6f),
from which the robot infers and which every perspective it models starts from.
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
    goal_marginals,
    least_cost_rows,
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

    def mix(self, observers, observations, goals: np.ndarray, configurations, priors,
            apply) -> list:  # fmt: skip
        """Each observer's prior over ``configurations`` (of goal indices ``goals``) made the
        type mixture, after scoring this step's moves, for all ``observers`` at once.

        ``priors`` holds one vector (or ``None``, uniform) per observer; where ``apply[r]``
        is false the moves are scored but the prior is returned as it is.
        """
        s, step = self.scenario, observations.step
        observers = np.asarray(observers, dtype=int)
        k = configurations.shape[0]
        pi = np.stack([np.full(k, 1.0 / k) if p is None else np.asarray(p, float) for p in priors])
        positions = observations.poses[observers][:, :, :2]  # (R, n, 2)
        seen = observations.seen[observers].copy()
        seen[np.arange(len(observers)), observers] = False
        where = s.goals[goals]
        self._score(observers, step, positions, seen, goals, where)
        marginal = goal_marginals(pi, configurations, goals.size)  # (R, n, m)
        convention = least_cost_rows(positions, where, configurations)  # (R, n)
        r, n = seen.shape
        predictions = type_goal_probabilities(
            marginal.reshape(r * n, -1), positions.reshape(r * n, 2), where, convention.ravel()
        ).reshape(r, n, len(TYPE_PRIOR), goals.size)
        for row, observer in enumerate(observers.tolist()):
            self._last[observer] = (step, positions[row], seen[row], goals, predictions[row])
        apply = np.asarray(apply, dtype=bool)
        mixed = pi.copy()
        if apply.any():
            mixed[apply] = mix_configurations(
                pi[apply],
                self._log_types[observers[apply]],
                predictions[apply],
                configurations,
                seen[apply],
                marginal[apply],
            )
        return [mixed[row] if apply[row] else priors[row] for row in range(r)]

    def _score(self, observers, step, positions, seen, goals, where) -> None:
        """Update the type posteriors from each observer's view of this step's moves."""
        rows, pairs, previous, predicted = [], [], [], []
        for row, observer in enumerate(observers.tolist()):
            last = self._last.get(observer)
            if last is None or last[0] != step - 1 or not np.array_equal(last[3], goals):
                continue
            scored = np.flatnonzero(seen[row] & last[2])
            rows.append(np.full(scored.size, row))
            pairs.append(scored)
            previous.append(last[1][scored])
            predicted.append(last[4][scored])
        if not pairs or not sum(p.size for p in pairs):
            return
        rows, pairs = np.concatenate(rows), np.concatenate(pairs)
        reach = self.scenario.max_speed[pairs] * self.scenario.dt
        ll = motion_log_likelihood(
            np.concatenate(previous), positions[rows, pairs], np.concatenate(predicted), where,
            reach, self.sigma,
        )  # fmt: skip
        who = observers[rows]
        self._log_types[who, pairs] = update_types(self._log_types[who, pairs], ll, self.leak)
