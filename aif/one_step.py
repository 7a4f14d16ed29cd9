"""One-step expected free energy of a robot standing at candidate positions.

Given, for every perspective (see :mod:`epistemica.aif.perspective`) and every candidate
position of the deciding robot ``i``, the per-robot log goal probabilities ``ln P_r``, the
three terms of the controller's expected free energy are (nats)::

    G(u) = w_p · ‖x_i'(u) − g*_i‖ / eta                   progress: −ln C of the distance
         + w_s · Σ_a ω_a KL[q_a'(u) ‖ C*] / Σ_a ω_a       risk of the predicted beliefs
         + ln 2 − I_q(S; R_u)                            reading: risk + ambiguity

``c*`` is the mode of ``i``'s current belief (column 0: ``i`` where it stands), ``g*_i``
its goal for ``i``, and ``C*`` puts ``1 − eps`` on ``c*`` plus ``eps`` spread uniformly.
``R_u`` is the reading of ``i``'s own sensors at the candidate, a binary channel with
``P(R = 1 | s) = L_u(s) / max L_u``.

The risk of a belief and the grouping of a modelled belief's rows by ``s_i`` (``O(m)``
per candidate) are :mod:`~epistemica.aif.belief_risk`'s. The ``(k x candidates)`` passes
of the root perspective are chunked to a bounded number of cells, and run in float32 for
large valid sets (:meth:`OneStepEFE.sized`).

Examples
--------
>>> from epistemica.aif.configurations import valid_configurations
>>> model = OneStepEFE([[10.0, 0.0], [-10.0, 0.0]], valid_configurations("allocation", 2, 2))
>>> log_p = np.log(np.full((1, 2, 2, 2), 0.5))  # one perspective, two candidates, no evidence
>>> terms, q, focal = model.terms(log_p, np.ones(1), 0, np.array([[9.0, 0.0], [0.0, 0.0]]))
>>> terms.progress.round(3).tolist(), q.round(9).tolist(), focal
([0.02, 0.2], [0.5, 0.5], 0)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.special import xlogy

from epistemica.aif._logspace import log_normalise
from epistemica.aif._validate import (
    as_distribution,
    as_finite,
    as_log_values,
    nonnegative,
    positive,
    positive_int,
)
from epistemica.aif.belief import PUBLISHED_WEIGHT
from epistemica.aif.belief_risk import Preference, at_rows, grouped_risk
from epistemica.aif.evidence import DEFAULT_ETA, check_robot
from epistemica.aif.row_index import RowIndex
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["CHUNK_CELLS", "FLOAT32_ROWS", "OneStepEFE", "Terms"]

#: Cells (valid rows x candidates) per chunk of the large passes: about 32 MB of float64.
CHUNK_CELLS = 4_000_000
#: From this many valid configurations on, :meth:`OneStepEFE.sized` passes use float32.
FLOAT32_ROWS = 20_000


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


class OneStepEFE:
    """The three terms of ``G`` over a valid set, for batches of candidate positions.

    Parameters
    ----------
    goals : array_like
        ``(m, 2)`` goal positions.
    configurations : array_like
        ``(k, n)`` valid configurations.
    update : {"bayes", "published"}
        Belief rule: ``q ∝ L · prior`` or ``softmax(w L + (1 - w) prior)``.
    weight : float
        ``w`` of the published rule, in ``[0, 1]``.
    preference_floor : float
        ``eps`` of the preferred distribution ``C*``, in ``(0, 1)``.
    progress_weight, social_weight : float
        Weights of the progress and belief-risk terms.
    eta : float
        Distance scale (m) of the progress term.
    dtype : {numpy.float64, numpy.float32}
        Precision of the ``(k x candidates)`` passes.
    chunk_cells : int
        At most this many ``(valid row, candidate)`` cells per pass.
    """

    def __init__(
        self,
        goals,
        configurations,
        *,
        update: str = "bayes",
        weight: float = PUBLISHED_WEIGHT,
        preference_floor: float = 0.01,
        progress_weight: float = 1.0,
        social_weight: float = 1.0,
        eta: float = DEFAULT_ETA,
        dtype=np.float64,
        chunk_cells: int = 4_000_000,
    ) -> None:
        self.goals = as_finite(goals, "goals", ndim=2, shape=(None, 2))
        self.index = RowIndex(configurations, self.goals.shape[0], dtype)
        self.configurations = self.index.configurations
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
        self.progress_weight = nonnegative(progress_weight, "progress_weight")
        self.social_weight = nonnegative(social_weight, "social_weight")
        self.preference_floor = float(preference_floor)
        if not 0.0 < self.preference_floor < 1.0:
            raise InvalidArgumentError("preference_floor must lie in (0, 1)", hint="e.g. 0.01")
        self.eta = positive(eta, "eta")
        self.chunk_cells = positive_int(chunk_cells, "chunk_cells", "e.g. 4_000_000")
        self.preference = Preference(self.configurations.shape[0], self.preference_floor)

    @classmethod
    def sized(cls, goals, configurations, **settings) -> OneStepEFE:
        """A model whose passes suit the size of the valid set (``settings``: the others).

        Large sets: the ``(k x candidates)`` passes are memory-bound, and float32 halves
        them from :data:`FLOAT32_ROWS` valid rows on. Log likelihoods are sums of ``n``
        terms of order 1, so the rounding stays near 1e-6 nats. Chunks of
        :data:`CHUNK_CELLS` cells.

        Examples
        --------
        >>> from epistemica.aif.configurations import valid_configurations
        >>> goals = np.arange(16.0).reshape(8, 2)
        >>> OneStepEFE.sized(goals, valid_configurations("allocation", 5, 8)).index.dtype
        <class 'numpy.float64'>
        >>> OneStepEFE.sized(goals, valid_configurations("allocation", 6, 8)).index.dtype
        <class 'numpy.float32'>
        """
        large = len(configurations) >= FLOAT32_ROWS
        dtype = np.float32 if large else np.float64
        return cls(goals, configurations, dtype=dtype, chunk_cells=CHUNK_CELLS, **settings)

    def posterior_log(self, log_p, prior=None) -> np.ndarray:
        """Log posteriors ``(k, b)`` from per-robot log goal probabilities ``(b, n, m)``.

        Examples
        --------
        >>> model = OneStepEFE([[0, 0], [1, 0]], [[0, 1], [1, 0]])
        >>> log_p = np.log([[[0.9, 0.1], [0.5, 0.5]]])
        >>> np.exp(model.posterior_log(log_p, [0.5, 0.5])).round(3).tolist()
        [[0.9], [0.1]]
        """
        n = self.configurations.shape[1]
        lp = as_log_values(log_p, "log_p", ndim=3, shape=(None, n, self.goals.shape[0]))
        return self.unchecked_posterior_log(lp, self._check_prior(prior))

    def _check_prior(self, prior) -> np.ndarray:
        k = self.configurations.shape[0]
        return np.full(k, 1.0 / k) if prior is None else as_distribution(prior, "prior", size=k)

    def unchecked_posterior_log(self, log_p: np.ndarray, prior: np.ndarray) -> np.ndarray:
        """The core of :meth:`posterior_log`, for arguments already validated."""
        with np.errstate(divide="ignore"):
            log_prior = np.log(prior)
        return self._posterior(self.index.row_sums(log_p), log_prior, prior)

    def _posterior(self, ll: np.ndarray, log_prior: np.ndarray, prior) -> np.ndarray:
        """Log posteriors ``(k, b)`` from unnormalised log likelihoods ``ll (k, b)``."""
        if log_prior.ndim == 1:  # one robot's; else one per column (the team call)
            log_prior, prior = log_prior[:, None], prior[:, None]
        if self.update == "bayes":
            return log_normalise(ll + log_prior, 0)
        like = np.exp(log_normalise(ll, 0))
        return log_normalise(self.weight * like + (1 - self.weight) * prior, 0)

    def terms(self, log_p, weights, robot: int, positions, prior=None):
        """``(Terms, q_root, focal)`` for ``robot`` at each of ``positions (c, 2)``.

        Parameters
        ----------
        log_p : array_like
            ``(P, c, n, m)`` log goal probabilities of each perspective (the first is the
            robot's own) with the robot at each position; column 0 is where it stands now.
        weights : array_like
            ``(P,)`` positive perspective weights.
        robot : int
            The deciding robot.
        positions : array_like
            ``(c, 2)`` the candidate positions matching the columns of ``log_p``.
        prior : array_like, optional
            Prior over the valid configurations (default uniform).

        Returns
        -------
        terms : Terms
            One entry per column.
        q_root : numpy.ndarray
            The robot's current belief (column 0).
        focal : int
            Its mode, the focal configuration.
        """
        n = self.configurations.shape[1]
        lp = as_log_values(log_p, "log_p", ndim=4, shape=(None, None, n, self.goals.shape[0]))
        w = as_finite(weights, "weights", ndim=1, shape=(lp.shape[0],))
        if w.size == 0 or np.any(w <= 0):
            raise InvalidArgumentError(
                "weights must be positive, one per perspective", hint="the root's weight is 1"
            )
        robot = check_robot(robot, n)
        batch = as_finite(positions, "positions", ndim=2, shape=(lp.shape[1], 2))
        return self.batch_terms(lp, w, robot, batch, self._check_prior(prior))

    def batch_terms(self, log_p, weights, robot, batch, prior, modelled=None):
        """Unchecked :meth:`terms`; ``prior`` is a probability vector, ``modelled`` None or
        ``(k, P - 1)`` priors of the modelled perspectives (default ``prior``)."""
        k = self.configurations.shape[0]
        c = batch.shape[0]
        with np.errstate(divide="ignore"):
            log_prior = np.log(prior)
        uniform = bool(np.all(prior == prior[0]))
        root_changed = bool(np.any(log_p[0, 1:] != log_p[0, :1]))
        q_root = np.exp(self._posterior(self.index.row_sums(log_p[0, :1]), log_prior, prior)[:, 0])
        focal = int(np.argmax(q_root))
        # (k x columns) passes are chunked so that huge valid sets stay within memory.
        step = max(1, self.chunk_cells // k)
        root_batch = log_p[0] if root_changed else log_p[0, :1]
        parts = [
            self.root_terms(
                self.index.row_sums(root_batch[a : a + step]),
                log_prior,
                prior,
                q_root,
                focal,
                uniform,
            )
            for a in range(0, root_batch.shape[0], step)
        ]
        risk_root = np.concatenate([p[0] for p in parts])
        reading = np.concatenate([p[1] for p in parts])
        risk = weights[0] * np.broadcast_to(risk_root, (c,))
        if len(weights) > 1:
            r = self.modelled_risk(log_p[1:], robot, focal, step, prior, log_prior, modelled)
            risk = risk + weights[1:] @ r
        g_star = self.goals[self.configurations[focal, robot]]
        progress = np.hypot(batch[:, 0] - g_star[0], batch[:, 1] - g_star[1]) / self.eta
        terms = Terms(
            progress=self.progress_weight * progress,
            belief_risk=self.social_weight * risk / weights.sum(),
            reading=np.broadcast_to(reading, (c,)),
        )
        return terms, q_root, focal

    def modelled_risk(self, views, robot, focal, step, prior, log_prior, modelled=None):
        """``KL[q'_a || C*]`` ``(P - 1, c)`` of the modelled perspectives ``views``
        (``log_p[1:]``), ``step`` columns or perspectives per pass; ``modelled`` as in
        :meth:`batch_terms`. Under the Bayes rule only ``robot``'s row moves, so the rows
        are grouped (:meth:`grouped_risk`)."""
        uniform = bool(np.all(prior == prior[0]))
        m_prior, m_log, m_uniform = prior, log_prior, uniform
        if modelled is not None:
            with np.errstate(divide="ignore"):
                m_prior, m_log = modelled, np.log(modelled)
            m_uniform = np.all(modelled == modelled[:1], axis=0)
        if self.update == "bayes":
            # Each modelled belief at column 0, and the robot's row in every column.
            movers = np.full(views.shape[0], robot)
            return np.concatenate(
                [
                    self.grouped_risk(
                        views[a : a + step, 0],
                        views[a : a + step, :, robot],
                        movers[a : a + step],
                        m_log if modelled is None else m_log[:, a : a + step],
                        focal,
                        m_uniform if modelled is None else m_uniform[a : a + step],
                    )
                    for a in range(0, views.shape[0], step)
                ]
            )
        else:
            return np.stack(
                [
                    np.concatenate(
                        [
                            self.preference.risk(
                                self._posterior(
                                    self.index.row_sums(lp[a : a + step]),
                                    m_log if modelled is None else m_log[:, p],
                                    m_prior if modelled is None else m_prior[:, p],
                                ),
                                focal,
                            )
                            for a in range(0, lp.shape[0], step)
                        ]
                    )
                    for p, lp in enumerate(views)
                ]
            )

    def grouped_risk(self, base, moved, movers, log_prior, focal, uniform) -> np.ndarray:
        """:func:`~epistemica.aif.belief_risk.grouped_risk` over this model's valid rows."""
        return grouped_risk(
            self.index, self.preference, base, moved, movers, log_prior, focal, uniform
        )

    def root_terms(self, ll: np.ndarray, log_prior, prior, q0, focal, uniform):
        """Belief risk and reading term of the robot's own perspective, per column of ``ll``.

        ``ll (k, b)`` are unnormalised log likelihoods of the valid rows; it is consumed
        (overwritten) to avoid fresh (k x b) buffers, whose page faults dominate here.
        In the team call the columns belong to several robots: ``log_prior``, ``prior`` and
        ``q0`` are then ``(k, b)``, ``focal`` and ``uniform`` ``(b,)``, one per column.
        """
        fast = np.logical_and(self.update == "bayes", uniform)
        if not np.all(fast):
            risk = slow = self.preference.risk(self._posterior(ll, log_prior, prior), focal)
        d = ll
        d -= ll.max(axis=0, keepdims=True)
        ell = np.exp(d)  # P(R = 1 | s) = L(s) / max L
        q0 = q0.astype(ell.dtype)  # mixed precision would leave the fast loops
        if np.any(fast):
            # q'(s) ∝ ell(s): reuse ell and d instead of a second exponential pass.
            z = ell.sum(axis=0)
            neg_h = np.einsum("kb,kb->b", ell, d) / z - np.log(z)
            risk = self.preference.kl(neg_h, at_rows(ell, focal) / z)
            if not np.all(fast):
                risk = np.where(fast, risk, slow)
        # I(S; R) = h(E_q ell) - E_q h(ell), h the binary entropy; ln ell = d exactly.
        weigh = "k,kb->b" if q0.ndim == 1 else "kb,kb->b"
        mean = np.clip(np.einsum(weigh, q0, ell), 0.0, 1.0)
        d *= ell  # ell ln ell
        log1m = np.zeros_like(ell)
        if ell.dtype == np.float64:
            np.log1p(-ell, out=log1m, where=ell < 1)
        one_minus = np.subtract(1, ell, out=ell)
        if log1m.dtype != np.float64:  # float32 log is vectorised, log1p is not (error < 1e-7)
            np.log(one_minus, out=log1m, where=one_minus > 0)
        log1m *= one_minus
        d += log1m
        e_h = -np.einsum(weigh, q0, d)
        h_mean = -(xlogy(mean, mean) + xlogy(1 - mean, 1 - mean))
        reading = np.log(2.0) - np.maximum(h_mean - e_h, 0.0)
        return risk, reading
