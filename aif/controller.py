"""Expected-free-energy controller: choose one robot's next control.

For robot ``i`` and each candidate control ``u`` (:mod:`~epistemica.aif.motion`: speed ×
heading change; turn first, then move ``v·dt`` along the new heading):

1. beliefs now, from CURRENT observations: ``i``'s own belief at its order of reasoning
   and, at order >= 2, ``i``'s model of each other robot's belief
   (:mod:`~epistemica.aif.perspective`); the focal configuration ``c*`` is the mode of
   ``i``'s belief, recomputed every call (no latching);
2. the predicted next pose of ``i``; the others are predicted to stay where observed;
3. the predicted evidence, likelihood and belief of every perspective. In ``i``'s OWN
   belief, ``i``'s row keeps its current evidence: ``i`` knows its own motion exactly, and
   counting it as evidence about its own goal makes the robot stubborn. In the modelled
   beliefs of the others, ``i``'s predicted pose is exactly the signal they receive;
4. the expected free energy, three terms in nats (:mod:`~epistemica.aif.one_step`)::

     G(u) = w_p · d(x_i'(u), g*_i) / eta          progress risk: -ln C of the outcome
          + w_s · mean_a KL[q_a'(u) || C*]        risk of predicted beliefs vs preference
          + ln 2 - I_q(S; R_u)                     reading: risk + ambiguity, epistemic

5. ``q(u) = softmax(-gamma · G)``; the control of least ``G`` (or a sample with a given
   generator) is returned.

With ``horizon > 1`` control sequences are searched breadth first with pruning of
dominated branches (:mod:`~epistemica.aif.search`), each step costing the one-step ``G``
at the predicted pose (beliefs held at their current values); the first control of the
cheapest sequence is returned (receding horizon: call again at the next step).

Examples
--------
>>> from epistemica.aif.configurations import valid_configurations
>>> goals = [[10.0, 0.0], [-10.0, 0.0]]
>>> ctrl = Controller(goals, ["range", "range"], valid_configurations("allocation", 2, 2),
...                   order=2)
>>> poses = [[8.0, 0.0, 0.0], [-8.0, 0.0, 0.0]]
>>> d = ctrl.decide(0, poses)
>>> d.control                                   # full speed, straight on, to goal 0
(1.0, 0.0)
>>> ctrl.configurations[d.focal].tolist()
[0, 1]
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from epistemica.aif._logspace import log_softmax
from epistemica.aif._validate import as_distribution, as_finite, nonnegative, positive
from epistemica.aif.belief import PUBLISHED_WEIGHT
from epistemica.aif.decision import Decision, choose
from epistemica.aif.evidence import (
    DEFAULT_ETA,
    DEFAULT_ETA_BEARING,
    check_order,
    check_robot,
    check_sensors,
)
from epistemica.aif.likelihood import check_configurations
from epistemica.aif.motion import control_grid, predict_poses
from epistemica.aif.one_step import OneStepEFE, Terms
from epistemica.aif.perspective import Perspective, perspectives, predicted_evidence
from epistemica.aif.search import MAX_BEAM, MAX_HORIZON, check_search, receding_horizon
from epistemica.aif.team import decide_team
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["MAX_BEAM", "MAX_HORIZON", "Controller", "Decision", "decide"]


class Controller:
    """Least-expected-free-energy control of one robot over valid goal configurations.

    Parameters
    ----------
    goals : array_like
        ``(m, 2)`` goal positions.
    sensors : sequence of {"range", "bearing"}
        One sensor type per robot.
    configurations : array_like
        ``(k, n)`` valid configurations (:func:`valid_configurations`).
    order : {0, 1, 2, 3}
        Order of reasoning.
    controls : array_like, optional
        ``(c, 2)`` candidate ``(speed, heading change)``; default :func:`control_grid`.
    dt, eta, eta_bearing : float
        Time step (s), range (m) and bearing (rad) evidence scales.
    gamma : float
        Policy precision.
    horizon, beam : int
        Look-ahead depth (at most :data:`MAX_HORIZON`), and surviving branches per first
        control and depth (at most :data:`MAX_BEAM`).
    update : {"bayes", "published"}
        Belief rule: ``q ∝ L · prior`` or the released code's
        ``softmax(w L + (1 - w) prior)`` with ``w = weight``.
    progress_weight, social_weight : float
        Weights of the progress and belief-risk terms. The progress default, 30 (0.6 nats
        per metre at eta = 50 m), was chosen by closed-loop trials on tuning seeds
        (docs/aif.md, "Closed-loop defaults"): at 1, fresh observation noise outweighs
        progress and robots dither short of an agreed goal.
    preference_floor : float
        ``eps`` of the preferred distribution ``C*`` over configurations.
    position_noise : float
        Variance (m², per axis) of the noise on the observed positions of the others. The
        evidence of each other robot's row is attenuated by the probit approximation
        ``1 / sqrt(1 + pi s² / 8)``, ``s²`` the variance the noise induces in that row's
        evidence (docs/aif.md, "Observation noise"): the likelihood is less confident at
        32 m² than at 0.5 m². 0 (default) trusts observations as exact.
    """

    def __init__(
        self,
        goals,
        sensors: Sequence[str],
        configurations,
        *,
        order: int = 1,
        controls=None,
        dt: float = 1.0,
        eta: float = DEFAULT_ETA,
        eta_bearing: float = DEFAULT_ETA_BEARING,
        gamma: float = 1.0,
        horizon: int = 1,
        beam: int = 4,
        update: str = "bayes",
        weight: float = PUBLISHED_WEIGHT,
        progress_weight: float = 30.0,
        social_weight: float = 1.0,
        preference_floor: float = 0.01,
        position_noise: float = 0.0,
    ) -> None:
        self.goals = as_finite(goals, "goals", ndim=2, shape=(None, 2))
        self.sensors = check_sensors(sensors)
        self.bearing = np.array([s == "bearing" for s in self.sensors])
        n, m = len(self.sensors), self.goals.shape[0]
        if n == 0 or m == 0:
            raise InvalidArgumentError(
                "need at least one robot and one goal", hint="pass non-empty goals and sensors"
            )
        self.configurations = check_configurations(configurations, n, m)
        self.order = check_order(order)
        self.controls = (
            control_grid()
            if controls is None
            else as_finite(controls, "controls", ndim=2, shape=(None, 2))
        )
        if self.controls.shape[0] == 0:
            raise InvalidArgumentError("no candidate control", hint="pass at least one")
        self.dt = positive(dt, "dt")
        self.eta = positive(eta, "eta")
        self.eta_bearing = positive(eta_bearing, "eta_bearing")
        self.gamma = nonnegative(gamma, "gamma", hint="a precision")
        self.horizon, self.beam = check_search(horizon, beam)
        self.model = OneStepEFE.sized(
            self.goals,
            self.configurations,
            update=update,
            weight=weight,
            preference_floor=preference_floor,
            progress_weight=progress_weight,
            social_weight=social_weight,
            eta=self.eta,
        )
        self.update, self.weight = self.model.update, self.model.weight
        self.progress_weight = self.model.progress_weight
        self.social_weight = self.model.social_weight
        self.preference_floor = self.model.preference_floor
        self._perspective_cache: dict[int, list[Perspective]] = {}
        self.chunk_cells = self.model.chunk_cells  # the team call's passes stay within one chunk
        self.position_noise = nonnegative(position_noise, "position_noise", hint="a variance, m²")

    def perspectives(self, robot: int) -> list[Perspective]:
        """The beliefs robot ``robot`` holds (first) or models, with their evidence chains.

        Examples
        --------
        >>> from epistemica.aif.configurations import valid_configurations
        >>> ctrl = Controller([[0, 0], [1, 1], [2, 2]], ["range", "bearing", "range"],
        ...                   valid_configurations("allocation", 3, 3), order=3)
        >>> [(p.agent, p.order, p.weight) for p in ctrl.perspectives(0)]
        [(0, 3, 1.0), (1, 2, 1.0), (2, 2, 1.0), (1, 1, 1.0)]
        """
        robot = check_robot(robot, len(self.sensors))
        if robot not in self._perspective_cache:
            self._perspective_cache[robot] = perspectives(self.sensors, robot, self.order)
        return self._perspective_cache[robot]

    def prior_vector(self, prior) -> np.ndarray:
        k = self.configurations.shape[0]
        if prior is None:
            return np.full(k, 1.0 / k)
        return as_distribution(prior, "prior", size=k)

    def _evidence(self, views, robot: int, pos: np.ndarray, xs: np.ndarray) -> np.ndarray:
        """Evidence ``(P, b, n, m)`` of ``views`` with ``robot`` at each of ``xs (b, 2)``."""
        return predicted_evidence(
            views,
            robot,
            pos,
            xs,
            self.goals,
            self.bearing,
            self.eta,
            self.eta_bearing,
            self.position_noise,
        )

    def beliefs(self, robot: int, poses, prior=None) -> tuple[np.ndarray, int]:
        """Robot ``robot``'s current belief over the configurations and its focal row.

        Examples
        --------
        >>> from epistemica.aif.configurations import valid_configurations
        >>> ctrl = Controller([[10, 0], [-10, 0]], ["range", "range"],
        ...                   valid_configurations("allocation", 2, 2))
        >>> q, focal = ctrl.beliefs(0, [[9.0, 0.0], [-9.0, 0.0]])
        >>> focal, bool(q[0] > q[1])
        (0, True)
        """
        robot = check_robot(robot, len(self.sensors))
        pos = checked_poses(poses, len(self.sensors))[:, :2]
        prior = self.prior_vector(prior)
        e = self._evidence(self.perspectives(robot)[:1], robot, pos, pos[robot][None])[0]
        q = np.exp(self.model.unchecked_posterior_log(log_softmax(e, -1), prior)[:, 0])
        return q, int(np.argmax(q))

    def evaluate(self, robot: int, poses, candidates, prior=None) -> np.ndarray:
        """Expected free energy of robot ``robot`` standing at each of ``candidates (b, 2)``.

        Examples
        --------
        >>> from epistemica.aif.configurations import valid_configurations
        >>> ctrl = Controller([[10, 0], [-10, 0]], ["range", "range"],
        ...                   valid_configurations("allocation", 2, 2), order=2)
        >>> G = ctrl.evaluate(0, [[5.0, 0.0], [-5.0, 0.0]], [[6.0, 0.0], [4.0, 0.0]])
        >>> bool(G[0] < G[1])  # closer to the focal goal, and more legible to robot 1
        True
        """
        return self.terms(robot, poses, candidates, prior).G

    def terms(self, robot: int, poses, candidates, prior=None) -> Terms:
        """The three terms of ``G`` for robot ``robot`` at each of ``candidates (b, 2)``.

        Examples
        --------
        >>> from epistemica.aif.configurations import valid_configurations
        >>> ctrl = Controller([[10, 0], [-10, 0]], ["range", "range"],
        ...                   valid_configurations("allocation", 2, 2))
        >>> t = ctrl.terms(0, [[5.0, 0.0], [-5.0, 0.0]], [[6.0, 0.0], [4.0, 0.0]])
        >>> t.progress.round(2).tolist(), bool(t.reading[0] == t.reading[1])  # 30 · d / 50
        ([2.4, 3.6], True)
        """
        robot = check_robot(robot, len(self.sensors))
        pos = checked_poses(poses, len(self.sensors))[:, :2]
        xs = as_finite(candidates, "candidates", ndim=2, shape=(None, 2))
        return self.evaluate_batch(robot, pos, xs, self.prior_vector(prior))[0]

    def evaluate_batch(self, robot, pos, xs, prior, modelled=None):
        views = self.perspectives(robot)
        weights = np.array([p.weight for p in views])
        # Column 0 is the current position; candidates that stop share it.
        stay = np.all(xs == pos[robot], axis=1)
        back = np.zeros(xs.shape[0], dtype=np.intp)
        back[~stay] = 1 + np.arange(np.count_nonzero(~stay))
        batch = np.concatenate([pos[robot][None], xs[~stay]])
        log_p = log_softmax(self._evidence(views, robot, pos, batch), -1)
        terms, q_root, focal = self.model.batch_terms(log_p, weights, robot, batch, prior, modelled)
        return Terms(*(t[back] for t in terms)), q_root, focal

    def _modelled(self, robot: int, priors) -> np.ndarray | None:
        """``(k, P - 1)`` priors of the modelled perspectives, validated, or None."""
        views = len(self.perspectives(robot)) - 1
        return modelled_priors(priors, views, self.configurations.shape[0])

    def decide(
        self,
        robot: int,
        poses,
        prior=None,
        rng: np.random.Generator | None = None,
        modelled_priors=None,
    ) -> Decision:
        """Choose robot ``robot``'s next control from the poses it observes.

        Parameters
        ----------
        robot : int
            Index of the deciding robot.
        poses : array_like
            ``(n, 3)`` poses ``x, y, heading`` as the robot observes them (its own exact);
            ``(n, 2)`` positions are read with heading 0.
        prior : array_like, optional
            Prior over the configurations (default uniform). Passing the previous
            posterior turns the controller into a filter; see docs/aif.md on latching.
        rng : numpy.random.Generator, optional
            Sample the control from ``q(u)`` with it; otherwise take the least ``G``.
        modelled_priors : sequence of array_like, optional
            One prior per modelled perspective (``perspectives(robot)[1:]``): what the
            robot thinks that teammate considers possible, e.g. zero on configurations the
            robot knows the teammate has ruled out (docs/aif.md, "Nested configuration
            sets"). Default: ``prior`` for every perspective.

        Examples
        --------
        >>> from epistemica.aif.configurations import valid_configurations
        >>> ctrl = Controller([[10, 0], [-10, 0]], ["range", "range"],
        ...                   valid_configurations("allocation", 2, 2), horizon=2)
        >>> ctrl.decide(0, [[9.5, 0.0, 0.0], [-9.0, 0.0, 0.0]]).control  # half a metre to go
        (0.3333333333333333, 0.0)
        """
        robot = check_robot(robot, len(self.sensors))
        poses = checked_poses(poses, len(self.sensors))
        prior = self.prior_vector(prior)
        modelled = self._modelled(robot, modelled_priors)
        pos = poses[:, :2]
        first = predict_poses(poses[robot], self.controls, self.dt)
        terms, q, focal = self.evaluate_batch(robot, pos, first[:, :2], prior, modelled)
        G = terms.G
        if self.horizon > 1:
            G = receding_horizon(
                lambda xs: self.evaluate_batch(robot, pos, xs, prior, modelled)[0].G,
                first,
                G,
                self.controls,
                self.dt,
                self.horizon,
                self.beam,
            )
        return choose(self.controls, self.gamma, G[None], [q], [focal], [rng])[0]

    def decide_team(self, observations, robots=None, priors=None, rng=None) -> list[Decision]:
        """Every robot's :meth:`decide` in one vectorised pass.

        Parameters
        ----------
        observations : array_like
            ``(n, n, 3)`` (or ``(n, n, 2)``): row ``i`` holds the poses robot ``i``
            observes, its own exact (the ``poses`` of ``decide(i, ...)``).
        robots : sequence of int, optional
            The deciding robots, distinct (default all, in index order).
        priors : sequence, optional
            One prior per deciding robot (each ``None`` or a vector), as ``decide``'s.
        rng : numpy.random.Generator or sequence of them, optional
            A single generator is drawn from once per robot in the order of ``robots``,
            exactly as the loop ``for i in robots: decide(i, ..., rng=rng)``; a sequence
            gives robot ``robots[j]`` the generator ``rng[j]``.

        Returns
        -------
        list of Decision
            ``[decide(i, observations[i], priors[j], ...) for j, i in enumerate(robots)]``,
            bit for bit; evidence and terms are computed for all robots together
            (docs/aif.md, "The team call").

        Examples
        --------
        >>> from epistemica.aif.configurations import valid_configurations
        >>> ctrl = Controller([[10, 0], [-10, 0]], ["range", "range"],
        ...                   valid_configurations("allocation", 2, 2), order=2)
        >>> seen = [[[8.0, 0.0, 0.0], [-8.0, 0.0, 3.0]], [[7.0, 1.0, 0.0], [-8.0, 0.0, np.pi]]]
        >>> team = ctrl.decide_team(seen)
        >>> [d.control for d in team]              # each drives on to its own goal
        [(1.0, 0.0), (1.0, 0.0)]
        >>> bool(np.array_equal(team[1].G, ctrl.decide(1, seen[1]).G))
        True
        """
        return decide_team(self, observations, robots, priors, rng)


def decide(
    robot: int, poses, goals, sensors, configurations, *, prior=None, rng=None, **options
) -> Decision:
    """One-call form of :meth:`Controller.decide` (``options`` go to :class:`Controller`).

    Examples
    --------
    >>> from epistemica.aif.configurations import valid_configurations
    >>> d = decide(0, [[0.0, 0.0, 0.0]], [[5.0, 0.0], [0.0, 5.0]], ["range"],
    ...            valid_configurations("allocation", 1, 2))
    >>> d.control
    (1.0, 0.0)
    """
    return Controller(goals, sensors, configurations, **options).decide(
        robot, poses, prior=prior, rng=rng
    )


def checked_poses(poses, n: int) -> np.ndarray:
    """``(n, 3)`` poses from ``(n, 2)`` positions (heading 0) or ``(n, 3)`` poses."""
    p = as_finite(poses, "poses", ndim=2, shape=(n, None))
    if p.shape[1] == 2:
        p = np.column_stack([p, np.zeros(n)])
    if p.shape[1] != 3:
        raise InvalidArgumentError(
            f"poses must be (n, 2) or (n, 3), got {p.shape}",
            hint="x, y and optionally heading per robot",
        )
    return p


def modelled_priors(priors, views: int, k: int) -> np.ndarray | None:
    """``(k, views)`` priors of the modelled perspectives, validated, or None."""
    if priors is None:
        return None
    if len(priors) != views:
        raise InvalidArgumentError(
            f"modelled_priors has {len(priors)} entries for {views} modelled perspectives",
            hint="one prior per perspective after the first of Controller.perspectives",
        )
    if views == 0:  # a robot that models nobody: nothing to stack
        return None
    return np.stack([as_distribution(p, "modelled prior", size=k) for p in priors], axis=1)
