"""The risk of a predicted belief: its divergence from the preferred distribution ``C*``.

``C*`` puts ``1 − eps`` on the focal configuration ``c*`` plus ``eps`` spread uniformly
over the ``k`` valid configurations, so ``KL[q ‖ C*] = −H[q] − E_q[ln C*]`` needs only the
negative entropy of ``q`` and its focal mass ``q(c*)`` (:class:`Preference`).

In a belief a robot models, only the deciding robot's row changes with the control, so
under the Bayes rule ``q'_u(s) ∝ w(s) exp(f_u[s_i])`` with ``w`` fixed: grouping the valid
rows by the goal ``s_i`` gives the normaliser, the entropy (between-group plus
within-group) and the focal mass from per-goal sums computed once, ``O(m)`` per candidate
(:func:`grouped_risk`).

Examples
--------
>>> pref = Preference(4, 0.01)
>>> q = np.array([0.7, 0.1, 0.1, 0.1])
>>> kl = float(pref.risk(np.log(q)[:, None], 0)[0])
>>> c_star = np.array([0.9925, 0.0025, 0.0025, 0.0025])   # 1 - eps + eps / k, eps / k
>>> bool(np.isclose(kl, np.sum(q * np.log(q / c_star))))
True
"""

from __future__ import annotations

import numpy as np

from epistemica.aif.row_index import RowIndex

__all__ = ["Preference", "at_rows", "grouped_risk"]


class Preference:
    """The preferred distribution ``C*`` over ``k`` valid configurations, floor ``eps``.

    Parameters
    ----------
    k : int
        Number of valid configurations.
    floor : float
        ``eps``, in ``(0, 1)`` (checked by the caller).
    """

    def __init__(self, k: int, floor: float) -> None:
        #: ``ln C*(c*)`` and ``ln C*(s)`` for ``s != c*``.
        self.ln_star = float(np.log(floor / k + 1 - floor))
        self.ln_other = float(np.log(floor / k))

    def kl(self, neg_h: np.ndarray, q_star: np.ndarray) -> np.ndarray:
        """``KL[q || C*] = -H[q] - E_q[ln C*]`` from ``-H[q]`` and the focal mass ``q(c*)``."""
        return np.maximum(neg_h - q_star * self.ln_star - (1 - q_star) * self.ln_other, 0.0)

    def risk(self, log_q: np.ndarray, focal) -> np.ndarray:
        """``KL[q || C*]`` for each column of ``log_q (k, b)`` (``focal``: one, or per column)."""
        q = np.exp(log_q)
        neg_h = np.einsum("kb,kb->b", q, np.where(q > 0, log_q, 0.0))
        return self.kl(neg_h, at_rows(q, focal))


def grouped_risk(
    index: RowIndex, preference: Preference, base, moved, movers, log_prior, focal, uniform
) -> np.ndarray:
    """``KL[q'_u || C*]`` of perspectives where only one robot's row moves: ``(P, c)``.

    ``base (P, n, m)`` are the log goal probabilities at column 0, ``moved (P, c, m)``
    the moving robot's row in every column, ``movers (P,)`` that robot. ``log_prior``,
    ``focal`` and ``uniform`` are one robot's, or per perspective (``(k, P)``, ``(P,)``)
    in the team call.

    Examples
    --------
    One modelled perspective of two robots and goals; robot 0 moves over two candidates.
    The result equals the divergence of the belief recomputed in full:

    >>> index = RowIndex([[0, 1], [1, 0], [0, 0]], 2)
    >>> base = np.log([[[0.6, 0.4], [0.3, 0.7]]])
    >>> moved = np.log([[[0.9, 0.1], [0.2, 0.8]]])
    >>> fast = grouped_risk(index, Preference(3, 0.01), base, moved, np.array([0]),
    ...                     np.zeros(3), 0, True)
    >>> full = []
    >>> for row in moved[0]:
    ...     scene = base[0].copy()
    ...     scene[0] = row
    ...     ll = index.row_sums(scene[None])
    ...     full.append(Preference(3, 0.01).risk(ll - np.log(np.exp(ll).sum()), 0)[0])
    >>> bool(np.allclose(fast[0], full))
    True
    """
    m = index.n_goals
    per = np.arange(base.shape[0])
    base = base.copy()
    base[per, movers] = 0.0
    b = index.row_sums(base)  # (k, P)
    if np.ndim(uniform) == 0:
        if not uniform:
            b = b + log_prior[:, None]
    elif not np.all(uniform):
        b = np.where(uniform, b, b + log_prior)
    b -= b.max(axis=0, keepdims=True)
    w = np.exp(b)
    # 0 · log 0 = 0: configurations with zero prior carry no mass and no entropy.
    wb = np.multiply(w, b, out=np.zeros_like(w), where=w > 0)
    # (P, m) in C order whatever the number of perspectives: einsum's rounding below
    # depends on its operands' memory layout, and the team call must match.
    if np.all(movers == movers[0]):
        groups = index.groups(int(movers[0]))
        mass = np.ascontiguousarray(np.asarray(groups @ w).T)
        tilt = np.ascontiguousarray(np.asarray(groups @ wb).T)
    else:  # several movers (team call): every robot's groups at once, then pick
        pick = movers[:, None] * m + np.arange(m)
        stacked = index.stacked_groups()
        mass = np.asarray(stacked @ w).T[per[:, None], pick]
        tilt = np.asarray(stacked @ wb).T[per[:, None], pick]
    with np.errstate(divide="ignore", invalid="ignore"):
        ln_mass = np.log(mass)
        h_within = np.where(mass > 0, ln_mass - tilt / np.where(mass > 0, mass, 1), 0.0)
    f = moved  # (P, c, m)
    logits = f + ln_mass[:, None, :]
    top = logits.max(axis=-1, keepdims=True)
    log_z = top + np.log(np.exp(logits - top).sum(axis=-1, keepdims=True))
    log_marg = logits - log_z
    marg = np.exp(log_marg)
    h = -np.sum(marg * np.where(marg > 0, log_marg, 0.0), axis=-1) + np.einsum(
        "pcm,pm->pc", marg, h_within
    )
    g_star = index.configurations[focal, movers]  # (P,)
    q_star = np.exp(at_rows(b, focal)[:, None] + f[per, :, g_star] - log_z[..., 0])
    return preference.kl(-h, q_star)


def at_rows(x: np.ndarray, rows) -> np.ndarray:
    """``x[rows]`` for one row; ``x[rows[j], j]`` for one row per column.

    Examples
    --------
    >>> at_rows(np.arange(6).reshape(3, 2), np.array([2, 0])).tolist()
    [4, 1]
    """
    return x[rows] if np.ndim(rows) == 0 else x[rows, np.arange(x.shape[1])]
