"""Expected-free-energy controller: choose one robot's next control.

For robot ``i`` and each candidate control ``u`` (speed × heading change; turn first,
then move ``v·dt`` along the new heading):

1. beliefs now, from CURRENT observations: ``i``'s own belief at its order of reasoning
   and, at order >= 2, ``i``'s model of each other robot's belief (the perspectives of
   :mod:`epistemica.aif.evidence`); the focal configuration ``c*`` is the mode of ``i``'s
   belief, recomputed every call (no latching);
2. the predicted next pose of ``i``; the others are predicted to stay where observed;
3. the predicted evidence, likelihood and belief of every perspective. In ``i``'s OWN
   belief, ``i``'s row keeps its current evidence: ``i`` knows its own motion exactly, and
   counting it as evidence about its own goal makes the robot stubborn. In the modelled
   beliefs of the others, ``i``'s predicted pose is exactly the signal they receive;
4. the expected free energy, three terms (nats)::

     G(u) = w_p · d(x_i'(u), g*_i) / eta          progress risk: -ln C of the outcome
          + w_s · mean_a KL[q_a'(u) || C*]        risk of predicted beliefs vs preference
          + ln 2 - I_q(S; R_u)                     reading: risk + ambiguity, epistemic

   ``C*`` puts ``1 - eps`` on ``c*`` (plus ``eps`` spread uniformly); ``R_u`` is the
   reading of ``i``'s own sensors at the predicted pose, a binary channel with
   ``P(R = 1 | s) = L_u(s) / max L_u`` (the encoding of the paper's likelihood used by
   the pymdp reference case ``paper_configs``); its epistemic value is the joint mutual
   information with the configuration, and it is zero when ``u`` cannot change it;
5. ``q(u) = softmax(-gamma · G)``; the control of least ``G`` (or a sample with a given
   generator) is returned.

With ``horizon > 1`` control sequences are searched breadth first, each step costing the
one-step ``G`` at the predicted pose (beliefs held at their current values). Under each
first control, branches that reach the same pose with a higher cost are dominated (the
future from a pose does not depend on the path) and pruned, then the ``beam`` cheapest
survive; the first control of the cheapest sequence is returned (receding horizon: call
again at the next step).

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
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.sparse import csr_matrix
from scipy.special import softmax, xlogy

from epistemica.aif._validate import as_distribution, as_finite, positive
from epistemica.aif.belief import PUBLISHED_WEIGHT
from epistemica.aif.evidence import (
    DEFAULT_ETA,
    DEFAULT_ETA_BEARING,
    _check_order,
    _check_robot,
    _sensors,
    _stack,
    chain_counts,
)
from epistemica.aif.free_energy import select_policy
from epistemica.aif.likelihood import check_configurations
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "DEFAULT_HEADING_CHANGES",
    "DEFAULT_SPEEDS",
    "Controller",
    "Decision",
    "Perspective",
    "Terms",
    "control_grid",
    "decide",
    "predict_poses",
]

#: Speeds (m/s) of the paper protocol; 0 is "stop".
DEFAULT_SPEEDS = (0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0)
#: Eight heading changes evenly spaced over the full turn, including 0 ("straight ahead").
DEFAULT_HEADING_CHANGES = tuple(np.linspace(-np.pi, np.pi, 8, endpoint=False))


def control_grid(speeds=DEFAULT_SPEEDS, heading_changes=DEFAULT_HEADING_CHANGES) -> np.ndarray:
    """All ``(speed, heading change)`` pairs, shape ``(len(speeds) * len(changes), 2)``.

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
    heading = np.angle(np.exp(1j * (p[..., 2:3] + u[:, 1])))  # wrap to (-pi, pi]
    x = p[..., 0:1] + u[:, 0] * dt * np.cos(heading)
    y = p[..., 1:2] + u[:, 0] * dt * np.sin(heading)
    return np.stack([x, y, heading], axis=-1)


# Cells (valid rows x candidates) per chunk of the large passes: about 32 MB of float64.
_CHUNK_CELLS = 4_000_000
# From this many valid configurations on, the controller's large passes use float32.
_FLOAT32_ROWS = 20_000


def _log_normalise(x: np.ndarray, axis: int) -> np.ndarray:
    """``x - logsumexp(x)`` along ``axis`` (plain numpy: scipy's checks cost more here)."""
    top = x.max(axis=axis, keepdims=True)
    top = np.where(np.isfinite(top), top, 0.0)
    return x - (top + np.log(np.exp(x - top).sum(axis=axis, keepdims=True)))


def _log_softmax(x: np.ndarray, axis: int) -> np.ndarray:
    shifted = x - x.max(axis=axis, keepdims=True)
    return shifted - np.log(np.exp(shifted).sum(axis=axis, keepdims=True))


class Terms(NamedTuple):
    """The terms of the controller's expected free energy, one entry per candidate.

    ``progress`` is the weighted ``-ln C`` of the distance to the focal goal;
    ``belief_risk`` the weighted mean ``KL[q'_a || C*]`` over the perspectives;
    ``reading`` is ``ln 2 - I(S; R)``: the reading channel's risk plus ambiguity under a
    flat preference (its epistemic value is ``ln 2 - reading``).
    """

    progress: np.ndarray
    belief_risk: np.ndarray
    reading: np.ndarray

    @property
    def G(self) -> np.ndarray:
        """Their sum, the expected free energy."""
        return self.progress + self.belief_risk + self.reading


@dataclass(frozen=True)
class Decision:
    """The outcome of one decision.

    Attributes
    ----------
    control : tuple of float
        The chosen ``(speed, heading change)``.
    index : int
        Its row in :attr:`Controller.controls`.
    G : numpy.ndarray
        Expected free energy of every candidate (best continuation when ``horizon > 1``).
    q_pi : numpy.ndarray
        Policy posterior ``softmax(-gamma G)`` over the candidates.
    belief : numpy.ndarray
        The robot's current belief over the valid configurations.
    focal : int
        Row of the focal (most probable) configuration.
    """

    control: tuple[float, float]
    index: int
    G: np.ndarray
    q_pi: np.ndarray
    belief: np.ndarray
    focal: int


class Perspective(NamedTuple):
    """A belief the deciding robot holds (``root``) or models for another robot.

    ``agent`` holds the belief, built from evidence up to ``order``; ``weight`` is the
    number of chains that lead to it; ``counts[v]`` is how many of its evidence chains of
    order >= 1 end at viewpoint ``v`` (its evidence is ``sum_v counts[v] * measurements(v)``
    plus its own position at order 0).
    """

    agent: int
    order: int
    weight: float
    root: bool
    counts: np.ndarray


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
        Look-ahead depth, and surviving branches per first control and depth.
    update : {"bayes", "published"}
        Belief rule: ``q ∝ L · prior`` or the released code's
        ``softmax(w L + (1 - w) prior)`` with ``w = weight``.
    progress_weight, social_weight : float
        Weights of the progress and belief-risk terms.
    preference_floor : float
        ``eps`` of the preferred distribution ``C*`` over configurations.
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
        progress_weight: float = 1.0,
        social_weight: float = 1.0,
        preference_floor: float = 0.01,
    ) -> None:
        self.goals = as_finite(goals, "goals", ndim=2, shape=(None, 2))
        self.sensors = _sensors(sensors)
        self._bearing = np.array([s == "bearing" for s in self.sensors])
        n, m = len(self.sensors), self.goals.shape[0]
        if n == 0 or m == 0:
            raise InvalidArgumentError(
                "need at least one robot and one goal", hint="pass non-empty goals and sensors"
            )
        self.configurations = check_configurations(configurations, n, m)
        self.order = _check_order(order)
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
        self.gamma = float(as_finite(gamma, "gamma"))
        if self.gamma < 0:
            raise InvalidArgumentError(f"gamma must be >= 0, got {gamma!r}", hint="a precision")
        for name, value in (("horizon", horizon), ("beam", beam)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise InvalidArgumentError(
                    f"{name} must be a positive integer, got {value!r}",
                    hint="horizon 1 is the one-step controller",
                )
        self.horizon, self.beam = int(horizon), int(beam)
        if update not in ("bayes", "published"):
            raise InvalidArgumentError(
                f"unknown update {update!r}", hint="use 'bayes' or 'published'"
            )
        self.update = update
        self.weight = float(as_finite(weight, "weight"))
        if not 0.0 <= self.weight <= 1.0:
            raise InvalidArgumentError(
                f"weight must lie in [0, 1], got {weight!r}", hint="the published runs use 0.2"
            )
        self.progress_weight = float(progress_weight)
        self.social_weight = float(social_weight)
        self.preference_floor = float(preference_floor)
        if not 0.0 < self.preference_floor < 1.0:
            raise InvalidArgumentError("preference_floor must lie in (0, 1)", hint="e.g. 0.01")
        self._onehot = None
        # Large sets: the (k x candidates) passes are memory-bound; float32 halves them. Log
        # likelihoods are sums of n terms of order 1, so the rounding stays near 1e-6 nats.
        self._dtype = np.float32 if self.configurations.shape[0] >= _FLOAT32_ROWS else np.float64
        self._group_cache: dict[int, csr_matrix] = {}
        self._perspective_cache: dict[int, list[Perspective]] = {}

    # -- perspectives -----------------------------------------------------------------

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
        robot = _check_robot(robot, len(self.sensors))
        if robot in self._perspective_cache:
            return self._perspective_cache[robot]
        out = [self._perspective(robot, self.order, 1.0, root=True)]
        if self.order >= 2:
            counts = chain_counts(self.sensors, robot, self.order)
            # An order-2 chain (i, j) ends at j: i's model of j's belief, one order lower.
            for j in np.flatnonzero(counts[2]):
                out.append(self._perspective(int(j), self.order - 1, float(counts[2, j])))
            if self.order >= 3:
                # An order-3 chain (i, j, k): i's model of j's model of k's belief.
                for k in np.flatnonzero(counts[3]):
                    out.append(self._perspective(int(k), self.order - 2, float(counts[3, k])))
        self._perspective_cache[robot] = out
        return out

    def _perspective(self, agent: int, order: int, weight: float, root=False) -> Perspective:
        counts = chain_counts(self.sensors, agent, order)
        return Perspective(agent, order, weight, root, counts[1:].sum(axis=0).astype(float))

    # -- evaluation ---------------------------------------------------------------------

    def _poses(self, poses) -> np.ndarray:
        n = len(self.sensors)
        p = as_finite(poses, "poses", ndim=2, shape=(n, None))
        if p.shape[1] == 2:
            p = np.column_stack([p, np.zeros(n)])
        if p.shape[1] != 3:
            raise InvalidArgumentError(
                f"poses must be (n, 2) or (n, 3), got {p.shape}",
                hint="x, y and optionally heading per robot",
            )
        return p

    def _prior(self, prior) -> np.ndarray:
        k = self.configurations.shape[0]
        if prior is None:
            return np.full(k, 1.0 / k)
        return as_distribution(prior, "prior", size=k)

    def _row_sums(self, tables: np.ndarray) -> np.ndarray:
        """``sum_r table[r, s_r]`` for every valid row, ``(b, n, m) -> (k, b)``, sparse."""
        if self._onehot is None:
            rows = self.configurations
            k, n = rows.shape
            m = self.goals.shape[0]
            flat = (rows + np.arange(n) * m).ravel()
            self._onehot = csr_matrix(
                (np.ones(k * n, dtype=self._dtype), flat, np.arange(0, k * n + 1, n)),
                shape=(k, n * m),
            )
        t = tables.reshape(tables.shape[0], -1).astype(self._dtype)
        return np.asarray(self._onehot @ t.T)

    def _groups(self, robot: int):
        """Sparse ``(m, k)`` indicator of each row's goal for ``robot``."""
        if robot not in self._group_cache:
            g = self.configurations[:, robot]
            k = g.size
            self._group_cache[robot] = csr_matrix(
                (np.ones(k, dtype=self._dtype), (g, np.arange(k))), shape=(self.goals.shape[0], k)
            )
        return self._group_cache[robot]

    def _evidence(self, perspectives, robot: int, pos: np.ndarray, xs: np.ndarray):
        """Evidence ``(P, b, n, m)`` of every perspective with ``robot`` at each ``xs (b, 2)``.

        Only what ``robot``'s motion can change is recomputed: in its own belief, its
        measurements of the others (its viewpoint moves; its own row stays); in a modelled
        belief, the others' measurements of ``robot`` (what they would see of it).
        """
        scenes = np.repeat(pos[None], xs.shape[0], axis=0)
        scenes[:, robot] = xs
        stack, ranged = _stack(scenes, self.goals, self._bearing, self.eta, self.eta_bearing)
        counts = np.array([p.counts for p in perspectives])
        e = np.tensordot(counts, stack, axes=([1], [1]))  # (P, b, n, m)
        agents = np.array([p.agent for p in perspectives])
        # Order 0: each perspective's agent knows its own position exactly.
        e[np.arange(len(perspectives)), :, agents] += ranged[:, agents].transpose(1, 0, 2)
        others = np.arange(len(self.sensors)) != robot
        e[0, :, robot] = e[0, 0, robot]  # own motion is not evidence about own goal
        e[1:, :, others] = e[1:, :1, others]
        return e

    def _posterior_log(self, log_p: np.ndarray, log_prior: np.ndarray, prior) -> np.ndarray:
        """Log posteriors ``(k, b)`` from per-robot log goal probabilities ``(b, n, m)``."""
        ll = self._row_sums(log_p)
        if self.update == "bayes":
            return _log_normalise(ll + log_prior[:, None], 0)
        like = np.exp(_log_normalise(ll, 0))
        return _log_normalise(self.weight * like + (1 - self.weight) * prior[:, None], 0)

    def _preference_logs(self) -> tuple[float, float]:
        k, eps = self.configurations.shape[0], self.preference_floor
        return float(np.log(eps / k + 1 - eps)), float(np.log(eps / k))

    def _risk(self, log_q: np.ndarray, focal: int) -> np.ndarray:
        """``KL[q || C*]`` for each column of ``log_q (k, b)``."""
        q = np.exp(log_q)
        neg_h = np.einsum("kb,kb->b", q, np.where(q > 0, log_q, 0.0))
        q_star = q[focal]
        ln_star, ln_other = self._preference_logs()
        return np.maximum(neg_h - q_star * ln_star - (1 - q_star) * ln_other, 0.0)

    def _root_terms(self, ll: np.ndarray, log_prior, prior, q0, focal: int, uniform: bool):
        """Belief risk and reading term of the robot's own perspective, per column of ``ll``.

        ``ll (k, b)`` are unnormalised log likelihoods of the valid rows; it is consumed
        (overwritten) to avoid fresh (k x b) buffers, whose page faults dominate here.
        """
        if self.update == "bayes" and not uniform:
            risk = self._risk(_log_normalise(ll + log_prior[:, None], 0), focal)
        elif self.update != "bayes":
            like = np.exp(_log_normalise(ll, 0))
            risk = self._risk(
                _log_normalise(self.weight * like + (1 - self.weight) * prior[:, None], 0), focal
            )
        d = ll
        d -= ll.max(axis=0, keepdims=True)
        ell = np.exp(d)  # P(R = 1 | s) = L(s) / max L
        q0 = q0.astype(ell.dtype)  # mixed precision would leave the fast loops
        if self.update == "bayes" and uniform:
            # q'(s) ∝ ell(s): reuse ell and d instead of a second exponential pass.
            z = ell.sum(axis=0)
            neg_h = np.einsum("kb,kb->b", ell, d) / z - np.log(z)
            q_star = ell[focal] / z
            ln_star, ln_other = self._preference_logs()
            risk = np.maximum(neg_h - q_star * ln_star - (1 - q_star) * ln_other, 0.0)
        # I(S; R) = h(E_q ell) - E_q h(ell), h the binary entropy; ln ell = d exactly.
        mean = np.clip(np.einsum("k,kb->b", q0, ell), 0.0, 1.0)
        d *= ell  # ell ln ell
        log1m = np.zeros_like(ell)
        if ell.dtype == np.float64:
            np.log1p(-ell, out=log1m, where=ell < 1)
        one_minus = np.subtract(1, ell, out=ell)
        if log1m.dtype != np.float64:  # float32 log is vectorised, log1p is not (error < 1e-7)
            np.log(one_minus, out=log1m, where=one_minus > 0)
        log1m *= one_minus
        d += log1m
        e_h = -np.einsum("k,kb->b", q0, d)
        h_mean = -(xlogy(mean, mean) + xlogy(1 - mean, 1 - mean))
        reading = np.log(2.0) - np.maximum(h_mean - e_h, 0.0)
        return risk, reading

    def _risk_fast(
        self, log_p: np.ndarray, robot: int, log_prior: np.ndarray, focal: int, uniform: bool
    ) -> np.ndarray:
        """``KL[q'_u || C*]`` of perspectives where only ``robot``'s row moves: ``(P, c)``.

        ``q'_u(s) ∝ w(s) exp(f_u[s_i])`` with ``w`` fixed, so grouping the rows by the goal
        ``s_i`` gives the normaliser, the entropy (between-group + within-group) and the
        focal mass from per-goal sums computed once: O(m) per candidate.
        """
        base = log_p[:, 0].copy()  # (P, n, m)
        base[:, robot] = 0.0
        b = self._row_sums(base)  # (k, P)
        if not uniform:
            b = b + log_prior[:, None]
        b -= b.max(axis=0, keepdims=True)
        w = np.exp(b)
        groups = self._groups(robot)
        mass = np.asarray(groups @ w).T  # (P, m)
        tilt = np.asarray(groups @ (w * b)).T
        with np.errstate(divide="ignore", invalid="ignore"):
            ln_mass = np.log(mass)
            h_within = np.where(mass > 0, ln_mass - tilt / np.where(mass > 0, mass, 1), 0.0)
        f = log_p[:, 1:, robot, :]  # (P, c, m)
        logits = f + ln_mass[:, None, :]
        top = logits.max(axis=-1, keepdims=True)
        log_z = top + np.log(np.exp(logits - top).sum(axis=-1, keepdims=True))
        log_marg = logits - log_z
        marg = np.exp(log_marg)
        h = -np.sum(marg * np.where(marg > 0, log_marg, 0.0), axis=-1) + np.einsum(
            "pcm,pm->pc", marg, h_within
        )
        g_star = self.configurations[focal, robot]
        q_star = np.exp(b[focal][:, None] + f[:, :, g_star] - log_z[..., 0])
        ln_star, ln_other = self._preference_logs()
        return np.maximum(-h - q_star * ln_star - (1 - q_star) * ln_other, 0.0)

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
        robot = _check_robot(robot, len(self.sensors))
        pos = self._poses(poses)[:, :2]
        prior = self._prior(prior)
        root = self.perspectives(robot)[:1]
        e = self._evidence(root, robot, pos, pos[robot][None])[0]
        with np.errstate(divide="ignore"):
            log_prior = np.log(prior)
        q = np.exp(self._posterior_log(_log_softmax(e, -1), log_prior, prior)[:, 0])
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
        >>> t.progress.round(2).tolist(), bool(t.reading[0] == t.reading[1])
        ([0.08, 0.12], True)
        """
        robot = _check_robot(robot, len(self.sensors))
        pos = self._poses(poses)[:, :2]
        xs = as_finite(candidates, "candidates", ndim=2, shape=(None, 2))
        return self._evaluate(robot, pos, xs, self._prior(prior))[0]

    def _evaluate(self, robot, pos, xs, prior):
        perspectives = self.perspectives(robot)
        weights = np.array([p.weight for p in perspectives])
        # Column 0 is the current position; candidates that stop share it.
        stay = np.all(xs == pos[robot], axis=1)
        back = np.zeros(xs.shape[0], dtype=np.intp)
        back[~stay] = 1 + np.arange(np.count_nonzero(~stay))
        batch = np.concatenate([pos[robot][None], xs[~stay]])
        c = batch.shape[0]
        log_p = _log_softmax(self._evidence(perspectives, robot, pos, batch), -1)
        with np.errstate(divide="ignore"):
            log_prior = np.log(prior)
        uniform = bool(np.all(prior == prior[0]))
        root_changed = bool(np.any(log_p[0, 1:] != log_p[0, :1]))
        q_root = np.exp(self._posterior_log(log_p[0, :1], log_prior, prior)[:, 0])
        focal = int(np.argmax(q_root))
        # (k x columns) passes are chunked so that huge valid sets stay within memory.
        step = max(1, _CHUNK_CELLS // self.configurations.shape[0])
        root_batch = log_p[0] if root_changed else log_p[0, :1]
        parts = [
            self._root_terms(
                self._row_sums(root_batch[a : a + step]), log_prior, prior, q_root, focal, uniform
            )
            for a in range(0, root_batch.shape[0], step)
        ]
        risk_root = np.concatenate([p[0] for p in parts])
        reading = np.concatenate([p[1] for p in parts])
        risk = weights[0] * np.broadcast_to(risk_root, (c,))
        if len(perspectives) > 1:
            if self.update == "bayes":
                # _risk_fast reads the base from column 0 and candidates from the rest.
                based = np.concatenate([log_p[1:, :1], log_p[1:]], axis=1)
                r = np.concatenate(
                    [
                        self._risk_fast(based[a : a + step], robot, log_prior, focal, uniform)
                        for a in range(0, len(perspectives) - 1, step)
                    ]
                )
            else:
                r = np.stack(
                    [
                        np.concatenate(
                            [
                                self._risk(
                                    self._posterior_log(lp[a : a + step], log_prior, prior), focal
                                )
                                for a in range(0, c, step)
                            ]
                        )
                        for lp in log_p[1:]
                    ]
                )
            risk = risk + weights[1:] @ r
        g_star = self.goals[self.configurations[focal, robot]]
        progress = np.hypot(batch[:, 0] - g_star[0], batch[:, 1] - g_star[1]) / self.eta
        terms = Terms(
            progress=(self.progress_weight * progress)[back],
            belief_risk=(self.social_weight * risk / weights.sum())[back],
            reading=np.broadcast_to(reading, (c,))[back],
        )
        return terms, q_root, focal

    # -- decision -------------------------------------------------------------------------

    def decide(
        self, robot: int, poses, prior=None, rng: np.random.Generator | None = None
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
        """
        robot = _check_robot(robot, len(self.sensors))
        poses = self._poses(poses)
        prior = self._prior(prior)
        pos = poses[:, :2]
        first = predict_poses(poses[robot], self.controls, self.dt)
        terms, q, focal = self._evaluate(robot, pos, first[:, :2], prior)
        G = terms.G
        if self.horizon > 1:
            G = self._search(robot, pos, first, G, prior)
        finite = np.isfinite(G)
        logits = np.where(finite, -self.gamma * np.where(finite, G, 0.0), -np.inf)
        q_pi = softmax(logits)
        if rng is None:
            best = np.flatnonzero(G == G[finite].min())
            index = int(best[0])
        else:
            index = select_policy(q_pi, rng)
        control = (float(self.controls[index, 0]), float(self.controls[index, 1]))
        return Decision(control, index, G, q_pi, q, focal)

    def _search(self, robot, pos, first, G1, prior) -> np.ndarray:
        """Best cumulative ``G`` over ``horizon`` steps for each first control."""
        c = self.controls.shape[0]
        nodes, cost, origin = first, G1.copy(), np.arange(c)
        for _ in range(1, self.horizon):
            nodes, cost, origin = self._prune(nodes, cost, origin)
            children = predict_poses(nodes[:, None, :], self.controls, self.dt).reshape(-1, 3)
            step = self._evaluate(robot, pos, children[:, :2], prior)[0].G
            cost = np.repeat(cost, c) + step
            origin = np.repeat(origin, c)
            nodes = children
        best = np.full(c, np.inf)
        np.minimum.at(best, origin, cost)
        return best

    def _prune(self, nodes, cost, origin):
        """Per first control: drop branches dominated by a cheaper one at the same pose
        (the future from a pose does not depend on how it was reached), then keep the
        ``beam`` cheapest. Every first control keeps a finite best cost."""
        key = np.round(nodes, 9)
        key[:, 2] = np.round(np.angle(np.exp(1j * nodes[:, 2])), 9)
        order = np.lexsort((cost, *key.T[::-1], origin))
        k_sorted, o_sorted = key[order], origin[order]
        new_pose = np.ones(len(order), dtype=bool)
        new_pose[1:] = np.any(k_sorted[1:] != k_sorted[:-1], axis=1) | (
            o_sorted[1:] != o_sorted[:-1]
        )
        keep = order[new_pose]
        keep = keep[np.lexsort((cost[keep], origin[keep]))]
        rank = np.arange(keep.size) - np.searchsorted(origin[keep], origin[keep], side="left")
        keep = keep[rank < self.beam]
        return nodes[keep], cost[keep], origin[keep]


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
