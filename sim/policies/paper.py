"""The released algorithm of the paper, as simulator levels, to reproduce its numbers.

Levels ``"paper-first"``, ``"paper-higher"`` and ``"paper-higher-fixed"`` follow what the
authors' released code did (``paper-results.md``, "Where the published code differs"),
not the paper's text:

- a perspective is a viewpoint ``v`` and one evidence type per robot row: range
  ``exp(-d / 50 m)`` of the robot's distance to each goal, or bearing ``cos`` of the angle
  at ``v`` between the robot and the goal (the released code's alignment; not
  ``exp(-angle)``, which made bearing robots chase angle changes instead of goals);
  per row ``softmax`` over goals, product over rows, normalised over the valid
  configurations: one likelihood ``L_p`` per perspective;
- first order: one perspective, the robot's own (its own row range, every other row its
  own sensor type);
- higher order: one perspective per robot ``p``, every row typed with the observer's
  sensor (its own row range when ``p`` is itself), none when a bearing observer would
  need a range robot's view (item 5). The released book-keeping overwrites the observer's
  type with each perspective's, so ``"paper-higher"`` keeps the slip: after its own
  perspective a bearing observer types every later one as range, and a range robot
  before it blanks every perspective up to its own; ``"paper-higher-fixed"`` does not.
  Bearing viewpoint rows keep the released angle to the goal from the x axis
  (``atan2(0, 0) = 0``). Each perspective keeps its own belief
  ``q_p <- softmax(0.2 L_p + 0.8 q_p)``;
- prediction, one step ahead with the robot at its predicted pose and the others where it
  observed them: first order ``q' = softmax(w L' + (1 - w) q)``; higher order the
  released consensus ``q' = softmax(w softmax(Σ_p L'_p) + (1 - w) softmax(n ·
  softmax(softmax(Σ_p q_p))))`` (item 3), ``w = 0.2`` (0.1 in multitask); ``q`` is the
  belief before this step's observations, which update it after the decision (the
  released order);
- every control of the published grid (speeds ``{0, 1/3, 2/3, 1}`` m/s, eight heading
  changes ``linspace(-π, π, 8)``, so no "straight ahead"; multitask ``{0.1, 0.4, 0.7, 1}``
  and ``linspace(-π/4, π/4, 8)``) is scored by ``H[q'] - ln max q'`` (item 2); the least
  score wins, exact ties broken at random (policy stream);
- multitask: each robot reasons over allocations of the ``n`` open tasks nearest itself
  (item 7); once fewer open tasks than robots remain, the released harness switches the
  robot to its greedy rule (drive straight to the nearest open task, turns clipped to the
  published ``±π/4``), and so does this level. The released multitask code
  (``aif_functions_iterative_sampling.py``) keeps one list of completed tasks for the
  whole team (a robot 10 m away from a task a teammate did knows it is done at once) and
  differs from the rendezvous code in six places; these levels follow it: bearing
  evidence ``(1 + cos) / 2`` (the same preference, in ``[0, 1]``) with a bearing viewpoint
  row uniform; each likelihood ``L_p = softmax`` of the products themselves, not the
  products normalised, so it stays close to uniform; every perspective typed afresh (no
  slip, also in ``"paper-higher"``); from :data:`SAMPLED_FROM` robots on, :data:`SAMPLES`
  random permutations of the task subset drawn every step (policy stream, repeats
  allowed) instead of all ``n!``, with ``-ln max q'`` counted once per entry at the
  maximum (:func:`free_energy`); and the beliefs kept entry by entry while no task is
  done, even when the nearest tasks change or come in another order (farthest first, as
  released), and started again from uniform when one is.

The valid configurations replace the released enumeration of all ``m^n`` combinations
(rendezvous, allocation): the likelihood is normalised over the same valid rows, so
beliefs and decisions are the same, at a fraction of the cost. Perspectives with no
evidence at all (every row blank) add the same constant to every configuration before a
``softmax`` and are skipped.

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> trial = simulate(Scenario.paper("allocation", 2, seed=0), "paper-higher", seed=0)
>>> trial.policies
('paper-higher', 'paper-higher')
"""

from __future__ import annotations

import numpy as np

from epistemica.aif.configurations import shared_configurations
from epistemica.aif.evidence import DEFAULT_ETA
from epistemica.aif.motion import control_grid, predict_poses
from epistemica.aif.row_index import RowIndex
from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.baselines import open_goals
from epistemica.sim.policies.policy import Decisions, Policy, steer

__all__ = [
    "PAPER_LEVELS",
    "PaperPolicy",
    "free_energy",
    "perspectives",
    "product_softmax",
    "sampled_permutations",
]

#: The released-algorithm levels and whether they model others / keep the slip.
PAPER_LEVELS = {
    "paper-first": (False, False),
    "paper-higher": (True, True),
    "paper-higher-fixed": (True, False),
}

#: Evidence types of a perspective's rows.
RANGE, BEARING, BLANK = 0, 1, 2

#: Multitask: from this team size on, the released code samples ``SAMPLES`` allocations.
SAMPLED_FROM, SAMPLES = 5, 200


def _published_grid(multitask: bool) -> np.ndarray:
    if multitask:
        return control_grid((0.1, 0.4, 0.7, 1.0), np.linspace(-np.pi / 4, np.pi / 4, 8))
    return control_grid((0.0, 1 / 3, 2 / 3, 1.0), np.linspace(-np.pi, np.pi, 8))


def perspectives(robot: int, sensors, higher: bool, slip: bool) -> list[tuple[int, np.ndarray]]:
    """``(viewpoint, row types)`` of every perspective ``robot`` evaluates.

    Row types are :data:`RANGE`, :data:`BEARING` or :data:`BLANK` (no evidence);
    perspectives whose rows are all blank are left out.

    Examples
    --------
    A bearing robot 1 between range robots 0 and 2: the slip blanks robot 0's view and its
    own others, then gives it robot 2's view in range; without the slip it keeps its own
    bearing view and cannot take either range robot's:

    >>> [(v, t.tolist()) for v, t in perspectives(1, ["range", "bearing", "range"], True, True)]
    [(1, [2, 0, 2]), (2, [0, 0, 0])]
    >>> [(v, t.tolist()) for v, t in perspectives(1, ["range", "bearing", "range"], True, False)]
    [(1, [1, 0, 1])]
    """
    n = len(sensors)
    own = RANGE if sensors[robot] == "range" else BEARING
    views = range(n) if higher else [robot]
    current, out = own, []
    for view in views:
        kind = current if slip else own
        blank = kind == BEARING and sensors[view] == "range"
        types = np.full(n, BLANK if blank else kind)
        if view == robot:
            types[robot] = RANGE  # the observer knows where it is
        current = types[robot]  # the slip: the released list is overwritten here
        if not (types == BLANK).all():
            out.append((view, types))
    return out


def sampled_permutations(n: int, count: int, generator: np.random.Generator) -> np.ndarray:
    """``(count, n)`` permutations of ``0..n-1`` drawn independently from ``generator``
    (repeats allowed), as the released multitask code samples allocations from 5 robots on.

    Examples
    --------
    >>> rows = sampled_permutations(5, 3, np.random.default_rng(0))
    >>> rows.shape, sorted(rows[0].tolist())
    ((3, 5), [0, 1, 2, 3, 4])
    """
    return generator.permuted(np.tile(np.arange(n), (count, 1)), axis=1)


def product_softmax(log_p: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``(b, k)``: ``softmax`` over the rows of the product ``prod_i p[i, rows[:, i]]``.

    The released multitask code applies a ``softmax`` to the products themselves (values
    in ``(0, 1]``), not to their logarithms, so the likelihood stays near uniform.

    Examples
    --------
    >>> p = np.log([[[0.5, 0.5], [0.8, 0.2]]])
    >>> product_softmax(p, np.array([[0, 1], [1, 0]])).round(4).tolist()   # 0.1 vs 0.4
    [[0.4256, 0.5744]]
    """
    products = np.exp(log_p[:, np.arange(rows.shape[1]), rows].sum(axis=2))  # (b, k)
    return _softmax(products, axis=1)


def free_energy(q: np.ndarray, every_top: bool = False) -> np.ndarray:
    """The released score ``H[q] - ln max q`` of each row of ``(c, k)`` beliefs.

    With ``every_top`` (the multitask code) ``-ln max q`` counts once per entry at the
    maximum, as the released one-hot marks every one (sampled allocations repeat).

    Examples
    --------
    >>> q = np.array([[0.5, 0.5], [0.25, 0.75]])
    >>> free_energy(q).round(4).tolist(), free_energy(q, every_top=True).round(4).tolist()
    ([1.3863, 0.85], [2.0794, 0.85])
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        plogp = np.where(q > 0, q * np.log(q), 0.0)
    top = q.max(axis=1)
    times = (q == top[:, None]).sum(axis=1) if every_top else 1
    return -plogp.sum(axis=1) - np.log(top) * times


def _softmax(x: np.ndarray, axis: int = -1) -> np.ndarray:
    """``exp(x) / sum exp(x)`` along ``axis`` (scipy's costs more than the whole step)."""
    e = np.exp(x - x.max(axis=axis, keepdims=True))
    return e / e.sum(axis=axis, keepdims=True)


def _evidence(
    scenes, goals, to_goal, ranged, view: int, types: np.ndarray, multitask: bool = False
) -> np.ndarray:
    """``(b, n, m)`` evidence of one perspective for a batch of scenes ``(b, n, 2)``.

    Bearing rows: ``cos`` of the angle at ``view`` between the robot and the goal; the
    multitask code rescales it to ``(1 + cos) / 2`` and leaves the viewpoint's own row
    uniform (``1 / m``) where the rendezvous code reads ``atan2(0, 0) = 0`` there.
    """
    out = np.where((types == RANGE)[None, :, None], ranged, 1.0 / goals.shape[0])
    if (types == BEARING).any():
        to_robot = scenes - scenes[:, view : view + 1]  # (b, n, 2); zero at the viewpoint
        a_robot = np.arctan2(to_robot[..., 1], to_robot[..., 0])
        a_goal = np.arctan2(to_goal[:, view, :, 1], to_goal[:, view, :, 0])  # (b, m)
        aligned = np.cos(a_goal[:, None, :] - a_robot[:, :, None])
        bearing = types == BEARING
        if multitask:
            aligned = (1.0 + aligned) / 2.0
            bearing = bearing & (np.arange(len(types)) != view)
        out = np.where(bearing[None, :, None], aligned, out)
    return out


class PaperPolicy(Policy):
    """The released algorithm at one of :data:`PAPER_LEVELS`."""

    #: ``views[robot]``: the ``(viewpoint, row types)`` it evaluates (set by ``start``).
    views: dict[int, list[tuple[int, np.ndarray]]]

    def __init__(self, level: str) -> None:
        self.higher, self.slip = PAPER_LEVELS[level]
        self.name = level

    def start(self, scenario, robots, generators) -> None:
        super().start(scenario, robots, generators)
        multitask = scenario.kind.tasks
        self.multitask = multitask
        self.weight = 0.1 if multitask else 0.2
        self.grid = _published_grid(multitask)
        self._index: dict[tuple, RowIndex] = {}
        self._belief: dict[int, tuple[bytes, np.ndarray]] = {}
        slip = self.slip and not multitask  # the multitask code builds each view afresh
        self.views = {
            int(r): perspectives(int(r), scenario.sensors, self.higher, slip) for r in self.robots
        }

    def _open(self, observations: Observations, robot: int) -> np.ndarray:
        """The open goals ``robot`` reasons over. Multitask: a task any robot saw done is
        done for all (the released harness keeps one list of completed tasks)."""
        if not self.multitask:
            return open_goals(self.scenario, observations, robot)
        done = observations.known_done.any(axis=0)
        return np.flatnonzero(observations.known_goals[robot] & ~done)

    def _goals(self, observations: Observations, robot: int) -> tuple[np.ndarray, np.ndarray]:
        """Goal indices reasoned over, and their configurations.

        Multitask: the ``n`` open tasks nearest the robot, farthest first (the released
        order), with every allocation of them, or from :data:`SAMPLED_FROM` robots on
        :data:`SAMPLES` permutations drawn afresh from the robot's policy stream; ``rows``
        is ``None`` when fewer than ``n`` remain (the robot then drives greedily, and the
        goals are ordered nearest first).
        """
        s, n = self.scenario, self.scenario.n_robots
        known = self._open(observations, robot)
        if not self.multitask:
            return known, s.configurations()
        view = observations.poses[robot, robot : robot + 1]
        nearest = known[np.argsort(distances(view, s.goals[known])[0], kind="stable")[:n]]
        if len(nearest) < n:
            return nearest, None
        if n < SAMPLED_FROM:
            return nearest[::-1], shared_configurations("allocation", n, n)
        return nearest[::-1], sampled_permutations(n, SAMPLES, self.generators[robot])

    def _likelihoods(self, robot, scenes, goals, rows) -> np.ndarray:
        """``(b, p, k)``: each perspective's likelihood over the valid rows, per scene."""
        index = None if self.multitask else self._row_index(rows, goals.shape[0])
        to_goal = goals[None, None] - scenes[:, :, None]  # (b, n, m, 2)
        ranged = np.exp(-np.hypot(to_goal[..., 0], to_goal[..., 1]) / DEFAULT_ETA)
        out = []
        for view, types in self.views[robot]:
            e = _evidence(scenes, goals, to_goal, ranged, view, types, self.multitask)
            log_p = e - np.log(np.exp(e).sum(axis=2, keepdims=True))
            if index is None:  # the released multitask code: a softmax of the products
                out.append(product_softmax(log_p, rows))
            else:
                out.append(_softmax(index.row_sums(log_p).T, axis=1))  # (b, k)
        return np.stack(out, axis=1)

    def _row_index(self, rows: np.ndarray, n_goals: int) -> RowIndex:
        key = (rows.shape, n_goals, rows.tobytes()[:64])
        index = self._index.get(key)
        if index is None:
            index = self._index[key] = RowIndex(rows, n_goals)
        return index

    def _predict(self, likelihood: np.ndarray, belief: np.ndarray) -> np.ndarray:
        """The predicted belief ``q'`` for each candidate's ``(c, p, k)`` likelihoods."""
        w = self.weight
        if not self.higher:
            return _softmax(w * likelihood[:, 0] + (1 - w) * belief[0], axis=1)
        n = self.scenario.n_robots
        prior = _softmax(n * _softmax(_softmax(belief.sum(axis=0))))
        return _softmax(w * _softmax(likelihood.sum(axis=1), axis=1) + (1 - w) * prior, axis=1)

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        s, n = self.scenario, self.scenario.n_robots
        out = Decisions.of(np.zeros((len(robots), 2)), np.full((len(robots), n), -1))
        out = out._replace(goal_belief=np.zeros((len(robots), s.n_goals)))
        for row, robot in enumerate(robots):
            goals, rows = self._goals(observations, robot)
            if goals.size == 0:
                continue  # nothing left that it knows of: hold position
            opened = self._open(observations, robot).tobytes()
            if rows is None:  # fewer tasks than robots: the released code turns greedy
                pose = observations.poses[robot, robot : robot + 1]
                out.controls[row] = steer(
                    pose, s.goals[goals[:1]], s.max_speed[robot], s.max_turn[robot], s.dt
                )[0]
                out.focal[row, robot] = goals[0]
                continue
            view = observations.poses[robot]
            first = predict_poses(view[robot], self.grid, s.dt)  # (c, 3)
            scenes = np.repeat(view[None, :, :2], len(first) + 1, axis=0)
            scenes[1:, robot] = first[:, :2]
            likelihood = self._likelihoods(robot, scenes, s.goals[goals], rows)
            belief = self._prior(robot, opened, likelihood.shape[1:])
            q_next = self._predict(likelihood[1:], belief)
            score = free_energy(q_next, every_top=self.multitask)
            best = np.flatnonzero(score == score.min())
            choice = best[0] if best.size == 1 else self.generators[robot].choice(best)
            out.controls[row] = self.grid[choice]
            # This step's observations update the belief after the decision (released order).
            w = self.weight
            belief = _softmax(w * likelihood[0] + (1 - w) * belief, axis=1)
            self._belief[robot] = (opened, belief)
            q_now = belief.mean(axis=0)
            out.focal[row] = goals[rows[int(np.argmax(q_now))]]
            out.entropy[row] = float(-np.sum(q_now * np.log(np.maximum(q_now, 1e-300))))
            out.considered[row] = rows.shape[0]
            out.goal_belief[row] = np.bincount(
                goals[rows[:, robot]], weights=q_now, minlength=s.n_goals
            )
        return out

    def belief(self, robot: int) -> np.ndarray | None:
        """A copy of ``robot``'s ``(p, k)`` perspective beliefs after its last decision
        (``None`` before the first), over the configurations it last reasoned over."""
        stored = self._belief.get(robot)
        return None if stored is None else stored[1].copy()

    def _prior(self, robot: int, opened: bytes, shape: tuple[int, int]) -> np.ndarray:
        """The robot's ``(p, k)`` perspective beliefs, uniform at the start and whenever a
        task is done (the released reset); kept, entry by entry, while the open tasks are
        the same, even when its nearest tasks (multitask) are others or in another order."""
        previous = self._belief.get(robot)
        if previous is None or previous[0] != opened or previous[1].shape != shape:
            return np.full(shape, 1.0 / shape[1])
        return previous[1]
