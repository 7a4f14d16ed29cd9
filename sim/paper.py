"""The released algorithm of the paper, as simulator levels, to reproduce its numbers.

Levels ``"paper-first"``, ``"paper-higher"`` and ``"paper-higher-fixed"`` follow what the
authors' released code did (``paper-results.md``, "Where the published code differs"),
not the paper's text:

- evidence ``exp(-d / 50 m)`` of a robot's distance to a goal for range perspectives, and
  ``exp(-angle)`` of the angle at the viewpoint between robot and goal for bearing ones;
  a robot's own row is its own (exact) distance;
- per robot ``softmax`` over goals, product over robots, normalised over the valid
  configurations: one likelihood ``L_p`` per perspective;
- higher order sums the configuration likelihoods of the perspectives, ``L = Σ_p L_p``
  (item 3). Robot ``i`` models robot ``j`` only when they carry the same sensor (item 5: a
  range robot does not emulate a bearing robot's angles). ``"paper-higher"`` keeps the
  book-keeping slip of item 5: a bearing robot models every higher-indexed robot, and
  with range information; ``"paper-higher-fixed"`` does not;
- belief ``q_t = softmax(w · L / ΣL + (1 - w) · q_{t-1})`` with ``w = 0.2`` (0.1 in
  multitask), the previous belief kept between steps (item 1);
- every control of the published grid (speeds ``{0, 1/3, 2/3, 1}`` m/s, eight heading
  changes ``linspace(-π, π, 8)``, so no "straight ahead"; multitask ``{0.1, 0.4, 0.7, 1}``
  and ``linspace(-π/4, π/4, 8)``) is scored by the predicted belief's ``H[q'] - ln max q'``
  (item 2), one step ahead, with the robot at its predicted pose and the others where it
  observed them; the least score wins, exact ties broken at random (policy stream);
- multitask: each robot reasons over allocations of the ``n`` open tasks nearest itself
  (item 7).

The valid configurations replace the released enumeration of all ``m^n`` combinations:
the likelihood is normalised over the same valid rows, so beliefs and decisions are the
same, at a fraction of the cost.

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> trial = simulate(Scenario.paper("allocation", 2, seed=0), "paper-higher", seed=0)
>>> trial.policies
('paper-higher', 'paper-higher')
"""

from __future__ import annotations

import numpy as np
from scipy.special import logsumexp, softmax

from epistemica.aif.evidence import DEFAULT_ETA, measurement_stack
from epistemica.aif.motion import control_grid, predict_poses
from epistemica.aif.row_index import RowIndex
from epistemica.sim.active import _allocations
from epistemica.sim.baselines import open_goals
from epistemica.sim.missions import distances
from epistemica.sim.policy import Decisions, Policy
from epistemica.sim.sensing import Observations

__all__ = ["PAPER_LEVELS", "PaperPolicy"]

#: The released-algorithm levels and whether they model others / keep the slip.
PAPER_LEVELS = {
    "paper-first": (False, False),
    "paper-higher": (True, True),
    "paper-higher-fixed": (True, False),
}


def _published_grid(multitask: bool) -> np.ndarray:
    if multitask:
        return control_grid((0.1, 0.4, 0.7, 1.0), np.linspace(-np.pi / 4, np.pi / 4, 8))
    return control_grid((0.0, 1 / 3, 2 / 3, 1.0), np.linspace(-np.pi, np.pi, 8))


class PaperPolicy(Policy):
    """The released algorithm at one of :data:`PAPER_LEVELS`."""

    def __init__(self, level: str) -> None:
        self.higher, self.slip = PAPER_LEVELS[level]
        self.name = level

    def start(self, scenario, robots, generators) -> None:
        super().start(scenario, robots, generators)
        multitask = scenario.mission == "multitask"
        self.weight = 0.1 if multitask else 0.2
        self.grid = _published_grid(multitask)
        self._index: dict[tuple, RowIndex] = {}
        self._belief: dict[int, tuple[bytes, np.ndarray]] = {}

    def _perspectives(self, robot: int) -> list[tuple[int, str]]:
        """(agent, evidence type) of every perspective robot ``robot`` holds or models."""
        sensors = self.scenario.sensors
        out = [(robot, sensors[robot])]
        if not self.higher:
            return out
        for j, sensor in enumerate(sensors):
            if j == robot:
                continue
            if self.slip and sensors[robot] == "bearing" and j > robot:
                out.append((j, "range"))  # the slip: range information it cannot have
            elif sensor == sensors[robot]:
                out.append((j, sensor))
        return out

    def _goals(self, observations: Observations, robot: int) -> tuple[np.ndarray, np.ndarray]:
        """Goal indices reasoned over, and their valid configurations."""
        s, n = self.scenario, self.scenario.n_robots
        known = open_goals(s, observations, robot)
        if s.mission != "multitask":
            return known, s.configurations()
        view = observations.poses[robot, robot : robot + 1]
        nearest = known[np.argsort(distances(view, s.goals[known])[0], kind="stable")[:n]]
        return nearest, _allocations(n, len(nearest)) if len(nearest) >= n else None

    def _log_likelihood(self, robot, scenes, goals, rows) -> np.ndarray:
        """``log L (b, k)``: the summed perspective likelihoods for each scene."""
        n = scenes.shape[1]
        key = (rows.shape, goals.shape[0], rows.tobytes()[:64])
        index = self._index.get(key)
        if index is None:
            index = self._index[key] = RowIndex(rows, goals.shape[0])
        d = np.hypot(*(scenes[:, :, None, :] - goals[None, None]).transpose(3, 0, 1, 2))
        ranged = np.exp(-d / DEFAULT_ETA)  # (b, n, m)
        bearing = measurement_stack(scenes, goals, ["bearing"] * n)  # (b, v, r, m)
        total = np.full((scenes.shape[0], rows.shape[0]), -np.inf)
        for agent, kind in self._perspectives(robot):
            e = ranged.copy() if kind == "range" else bearing[:, agent].copy()
            e[:, agent] = ranged[:, agent]  # the agent knows where it is
            log_p = e - logsumexp(e, axis=2, keepdims=True)
            ll = index.row_sums(log_p).T  # (b, k)
            total = np.logaddexp(total, ll - logsumexp(ll, axis=1, keepdims=True))
        return total

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        s, n = self.scenario, self.scenario.n_robots
        out = Decisions.of(np.zeros((len(robots), 2)), np.full((len(robots), n), -1))
        out = out._replace(goal_belief=np.zeros((len(robots), s.n_goals)))
        for row, robot in enumerate(robots):
            goals, rows = self._goals(observations, robot)
            if rows is None or goals.size == 0:
                continue  # too few tasks left to reason over: stand still
            view = observations.poses[robot]
            first = predict_poses(view[robot], self.grid, s.dt)  # (c, 3)
            scenes = np.repeat(view[None, :, :2], len(first) + 1, axis=0)
            scenes[1:, robot] = first[:, :2]
            likelihood = np.exp(self._log_likelihood(robot, scenes, s.goals[goals], rows))
            likelihood /= likelihood.sum(axis=1, keepdims=True)
            q_now = self._update(robot, goals, likelihood[0])
            w = self.weight
            q_next = softmax(w * likelihood[1:] + (1 - w) * q_now, axis=1)
            with np.errstate(divide="ignore"):
                plogp = np.where(q_next > 0, q_next * np.log(q_next), 0.0)
            score = -plogp.sum(axis=1) - np.log(q_next.max(axis=1))
            best = np.flatnonzero(score == score.min())
            choice = best[0] if best.size == 1 else self.generators[robot].choice(best)
            out.controls[row] = self.grid[choice]
            out.focal[row] = goals[rows[int(np.argmax(q_now))]]
            out.entropy[row] = float(-np.sum(q_now * np.log(np.maximum(q_now, 1e-300))))
            out.considered[row] = rows.shape[0]
            out.goal_belief[row] = np.bincount(
                goals[rows[:, robot]], weights=q_now, minlength=s.n_goals
            )
        return out

    def _update(self, robot: int, goals: np.ndarray, likelihood: np.ndarray) -> np.ndarray:
        key = goals.tobytes()
        previous = self._belief.get(robot)
        if previous is None or previous[0] != key:  # new task set: start uniform
            prior = np.full(likelihood.size, 1.0 / likelihood.size)
        else:
            prior = previous[1]
        q = softmax(self.weight * likelihood + (1 - self.weight) * prior)
        self._belief[robot] = (key, q)
        return q
