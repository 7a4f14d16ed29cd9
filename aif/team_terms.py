"""The expected free energy of every robot of a team in one pass (private).

:meth:`OneStepEFE.batch_terms` handles one robot: its root perspective over the candidate
columns, its modelled perspectives grouped by goal. Here the same passes run once for the
whole team: the root columns of all robots side by side in one ``(k, columns)`` array
(a robot whose root does not change with its move contributes one column, as in the
single call), and the modelled perspectives of all robots in one ``(k, perspectives)``
array, each column with its robot's prior, focal configuration and mover. Used by
:mod:`~epistemica.aif.team` for the Bayes rule when both arrays stay within the chunk
size; otherwise it falls back to one ``batch_terms`` call per robot.
"""

from __future__ import annotations

import numpy as np

from epistemica.aif._logspace import log_normalise

__all__: list[str] = []


def team_terms(model, log_base, log_moved, log_root, start, weights, robots, batch, priors):
    """``G (R, b)`` per robot and column, current beliefs ``(R, k)`` and focal rows ``(R,)``.

    Parameters
    ----------
    model : OneStepEFE
        The controller's model (Bayes rule).
    log_base : numpy.ndarray
        ``(Q, n, m)`` log goal probabilities of every perspective at column 0; robot ``r``
        owns perspectives ``start[r]:start[r + 1]``, its root first.
    log_moved : numpy.ndarray
        ``(Q, b, m)`` the deciding robot's row of each perspective in every column.
    log_root : numpy.ndarray
        ``(R, b, n, m)`` each robot's root perspective in every column.
    start : numpy.ndarray
        ``(R + 1,)`` perspective offsets.
    weights : numpy.ndarray
        ``(Q,)`` perspective weights.
    robots : numpy.ndarray
        ``(R,)`` the deciding robots.
    batch : numpy.ndarray
        ``(R, b, 2)`` candidate positions, column 0 where each robot stands.
    priors : numpy.ndarray
        ``(R, k)`` one prior per robot.
    """
    R, b = batch.shape[:2]
    roots = start[:-1]
    owner = np.repeat(np.arange(R), np.diff(start))
    with np.errstate(divide="ignore"):
        log_prior = np.log(priors)
    uniform = np.all(priors == priors[:, :1], axis=1)
    # Current beliefs; transposed so that each robot's sum runs as in its own call.
    now = model.index.row_sums(log_base[roots]).T + log_prior
    q_root = np.exp(log_normalise(now, 1))
    focal = np.argmax(q_root, axis=1)
    # Root: all columns of a robot whose viewpoint moves, else its column 0 only. A lone
    # column's sums over the valid rows run pairwise, a block's row by row: the robots
    # with one column go in a column-major block, where each column's sums run pairwise.
    changed = np.any(log_root[:, 1:] != log_root[:, :1], axis=(1, 2, 3))
    risk_root, reading = np.empty((R, b)), np.empty((R, b))
    for group, order in ((np.flatnonzero(changed), "C"), (np.flatnonzero(~changed), "F")):
        if group.size == 0:
            continue
        width = b if order == "C" else 1
        col = np.repeat(group, width)
        ll = model.index.row_sums(log_root[group, :width].reshape(-1, *log_root.shape[2:]))
        risk, read = model.root_terms(
            *(
                np.asarray(a, order=order)
                for a in (ll, log_prior.T[:, col], priors.T[:, col], q_root.T[:, col])
            ),
            focal[col],
            uniform[col],
        )
        risk_root[group] = risk.reshape(group.size, width)
        reading[group] = read.reshape(group.size, width)
    # Modelled beliefs: only the mover's row changes.
    rest = np.setdiff1d(np.arange(len(weights)), roots)
    if rest.size:
        who = owner[rest]
        risk_rest = model.grouped_risk(
            log_base[rest],
            log_moved[rest],
            robots[who],
            log_prior.T[:, who],
            focal[who],
            uniform[who],
        )
    goal = model.goals[model.configurations[focal, robots]]  # (R, 2)
    progress = np.hypot(batch[..., 0] - goal[:, :1], batch[..., 1] - goal[:, 1:]) / model.eta
    G = np.empty((R, b))
    for r in range(R):
        w = weights[start[r] : start[r + 1]]
        risk = w[0] * risk_root[r]
        if len(w) > 1:
            risk = risk + w[1:] @ risk_rest[start[r] - r : start[r + 1] - r - 1]
        social = model.social_weight * risk / w.sum()
        G[r] = model.progress_weight * progress[r] + social + reading[r]
    return G, q_root, focal
