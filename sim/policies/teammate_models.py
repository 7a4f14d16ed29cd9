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
    goal_distances,
    goal_marginals,
    goal_probabilities_from_distances,
    least_cost_from_distances,
    mix_configurations,
    motion_log_likelihood,
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
        # the last call's ((step, observers, goals), positions, seen, predictions), batched
        self._batch: tuple | None = None

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
        pi = np.empty((observers.size, k))
        for row, p in enumerate(priors):
            pi[row] = 1.0 / k if p is None else p
        positions = observations.poses[observers][:, :, :2]  # (R, n, 2)
        seen = observations.seen[observers].copy()
        seen[np.arange(len(observers)), observers] = False
        where = s.goals[goals]
        self._score(observers, step, positions, seen, goals, where)
        marginal = goal_marginals(pi, configurations, goals.size)  # (R, n, m)
        distance = goal_distances(positions, where)  # (R, n, m), shared by the two below
        convention = least_cost_from_distances(distance, configurations)  # (R, n)
        r, n = seen.shape
        predictions = goal_probabilities_from_distances(
            marginal.reshape(r * n, -1), distance.reshape(r * n, -1), convention.ravel()
        ).reshape(r, n, len(TYPE_PRIOR), goals.size)
        for row, observer in enumerate(observers.tolist()):
            self._last[observer] = (step, positions[row], seen[row], goals, predictions[row])
        self._batch = ((step, observers.tobytes(), goals.tobytes()), positions, seen, predictions)
        apply = np.asarray(apply, dtype=bool)
        if apply.all():  # the usual case: no rows to pick
            mixed = mix_configurations(
                pi, self._log_types[observers], predictions, configurations, seen, marginal
            )
            return list(mixed)
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
        batch = self._batch
        if batch is not None and batch[0] == (step - 1, observers.tobytes(), goals.tobytes()):
            # the usual case: the same team decided together last step, on the same goals
            rows, pairs = np.nonzero(seen & batch[2])
            previous, predicted = batch[1][rows, pairs], batch[3][rows, pairs]
        else:
            rows, pairs, previous, predicted = self._scored_one_by_one(observers, step, seen, goals)
        if not pairs.size:
            return
        reach = self.scenario.max_speed[pairs] * self.scenario.dt
        ll = motion_log_likelihood(
            previous, positions[rows, pairs], predicted, where, reach, self.sigma
        )
        who = observers[rows]
        self._log_types[who, pairs] = update_types(self._log_types[who, pairs], ll, self.leak)

    def _scored_one_by_one(self, observers, step, seen, goals) -> tuple:
        """``(rows, teammates, previous positions, predictions)`` of the moves to score,
        from each observer's own record of the last step."""
        rows, pairs, previous, predicted = [np.zeros(0, int)], [np.zeros(0, int)], [], []
        for row, observer in enumerate(observers.tolist()):
            last = self._last.get(observer)
            if last is None or last[0] != step - 1 or not np.array_equal(last[3], goals):
                continue
            scored = np.flatnonzero(seen[row] & last[2])
            rows.append(np.full(scored.size, row))
            pairs.append(scored)
            previous.append(last[1][scored])
            predicted.append(last[4][scored])
        if not previous:
            return rows[0], pairs[0], None, None
        return (np.concatenate(rows), np.concatenate(pairs), np.concatenate(previous),
                np.concatenate(predicted))  # fmt: skip
