"""One decision per robot of a team in one pass: :meth:`Controller.decide_team`.

``n`` separate :meth:`~epistemica.aif.Controller.decide` calls repeat per call what does
not depend on the robot (argument checks, the motion model, the measurement stack, the
normalisation of evidence) as many small numpy operations. Here the robots' candidate
scenes are stacked along a leading robot axis and measured in one pass; the perspectives
of all robots are concatenated along one axis (robot ``r`` owns a contiguous block), so
evidence, attenuation and log goal probabilities are one pass each, and the expected free
energy terms of all robots are computed together (:mod:`~epistemica.aif.team_terms`).

Nothing of size ``m^n`` is built: the arrays are those of the ``n`` calls side by side.
Every operation is elementwise, or reduces along an axis that has the same length and
layout as in the single-robot call, so the results are those of ``n`` :meth:`decide`
calls bit for bit (tests/aif/test_aif_team.py checks it on random scenes).

Examples
--------
>>> from epistemica.aif import Controller, valid_configurations
>>> ctrl = Controller([[10, 0], [-10, 0]], ["range", "range"],
...                   valid_configurations("allocation", 2, 2), order=2)
>>> seen = [[[8.0, 0.0, 0.0], [-8.0, 0.0, np.pi]]] * 2   # both robots see the same scene
>>> [d.control for d in ctrl.decide_team(seen)]
[(1.0, 0.0), (1.0, 0.0)]
"""

from __future__ import annotations

import weakref
from typing import NamedTuple

import numpy as np

from epistemica.aif._logspace import log_softmax
from epistemica.aif._validate import as_finite
from epistemica.aif.decision import choose
from epistemica.aif.evidence import angle_batch, check_robot, noise_attenuation, stack_evidence
from epistemica.aif.motion import turn_then_move
from epistemica.aif.one_step import Terms
from epistemica.aif.perspective import chain_sums, row_weights
from epistemica.aif.search import receding_horizon
from epistemica.aif.team_terms import team_terms
from epistemica.del_.errors import InvalidArgumentError

__all__: list[str] = []


class _Views(NamedTuple):
    """One robot's perspectives as arrays (built once per robot and controller)."""

    counts: np.ndarray  # (P, n) chain ends per viewpoint
    agents: np.ndarray  # (P,) holder of each belief
    weights: np.ndarray  # (P,) perspective weights
    rows: np.ndarray  # (P, n) evidence terms per row (row_weights)


# Per controller (weakly: controllers built per step come and go), robot -> its views.
_VIEWS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _views(ctrl, robot: int) -> _Views:
    cache = _VIEWS.setdefault(ctrl, {})
    if robot not in cache:
        views = ctrl.perspectives(robot)
        cache[robot] = _Views(
            np.array([p.counts for p in views]),
            np.array([p.agent for p in views]),
            np.array([p.weight for p in views]),
            row_weights(views, len(ctrl.sensors)),
        )
    return cache[robot]


def _observations(ctrl, observations) -> np.ndarray:
    n = len(ctrl.sensors)
    obs = as_finite(observations, "observations", ndim=3, shape=(n, n, None))
    if obs.shape[2] == 2:
        obs = np.concatenate([obs, np.zeros((n, n, 1))], axis=2)
    if obs.shape[2] != 3:
        raise InvalidArgumentError(
            f"observations must be (n, n, 2) or (n, n, 3), got {obs.shape}",
            hint="row i: the poses robot i observes, its own exact",
        )
    return obs


def _per_robot(values, count: int, name: str) -> list:
    if values is None:
        return [None] * count
    if isinstance(values, np.random.Generator):
        return [values] * count  # one stream, consumed in the order of the robots
    values = list(values)
    if len(values) != count:
        raise InvalidArgumentError(
            f"{name} must have one entry per deciding robot ({count}), got {len(values)}",
            hint=f"pass None or a sequence of {count}",
        )
    return values


def decide_team(ctrl, observations, robots=None, priors=None, rng=None) -> list:
    """Unchecked-controller core of :meth:`Controller.decide_team` (see there)."""
    n = len(ctrl.sensors)
    obs = _observations(ctrl, observations)
    robots = np.arange(n) if robots is None else np.asarray(robots)
    if robots.ndim != 1 or len(set(robots.tolist())) != robots.size:
        raise InvalidArgumentError(
            "robots must be a sequence of distinct robot indices", hint="e.g. [0, 2, 3]"
        )
    robots = np.array([check_robot(r, n) for r in robots.tolist()], dtype=np.intp)
    priors = [ctrl.prior_vector(p) for p in _per_robot(priors, robots.size, "priors")]
    rngs = _per_robot(rng, robots.size, "rng")
    if robots.size == 0:
        return []
    own = obs[robots, robots]  # (R, 3) each robot's own pose
    first = turn_then_move(own[:, None, :], ctrl.controls, ctrl.dt)  # (R, c, 3)
    stay = np.all(first[..., :2] == own[:, None, :2], axis=2)
    moving = np.count_nonzero(~stay, axis=1)
    G = np.empty((robots.size, ctrl.controls.shape[0]))
    beliefs, focals = [None] * robots.size, np.empty(robots.size, dtype=np.intp)
    # Robots with as many distinct candidate positions share one pass (normally all).
    for b in np.unique(moving):
        group = np.flatnonzero(moving == b)
        g, q, f = _pass(ctrl, obs, robots[group], first[group], stay[group], priors, group)
        G[group], focals[group] = g, f
        for row, belief in zip(group.tolist(), q, strict=True):
            beliefs[row] = belief
    if ctrl.horizon > 1:
        for row, robot in enumerate(robots.tolist()):
            pos, prior = obs[robot, :, :2], priors[row]
            G[row] = receding_horizon(
                lambda xs, robot=robot, pos=pos, prior=prior: (
                    ctrl.evaluate_batch(robot, pos, xs, prior)[0].G
                ),
                first[row],
                G[row],
                ctrl.controls,
                ctrl.dt,
                ctrl.horizon,
                ctrl.beam,
            )
    return choose(ctrl.controls, ctrl.gamma, G, beliefs, focals, rngs)


def _pass(ctrl, obs, robots, first, stay, priors, rows):
    """``G (R, c)``, beliefs and focal rows of robots with equally many moving candidates."""
    R, c = first.shape[:2]
    at = np.arange(R)
    pos = obs[robots, :, :2]  # (R, n, 2)
    b = 1 + int(np.count_nonzero(~stay[0]))
    # Column 0 is the current position; candidates that stop share it.
    batch = np.empty((R, b, 2))
    batch[:, 0] = pos[at, robots]
    batch[:, 1:] = first[..., :2][~stay].reshape(R, b - 1, 2)
    back = np.zeros((R, c), dtype=np.intp)
    back[~stay] = np.tile(np.arange(1, b), R)
    stack, ranged = _scene_stack(ctrl, pos, robots, batch)
    views = [_views(ctrl, r) for r in robots.tolist()]
    sizes = [len(v.agents) for v in views]
    start = np.concatenate([[0], np.cumsum(sizes)])
    owner = np.repeat(at, sizes)
    agents = np.concatenate([v.agents for v in views])
    # (Q, b, n, m): per robot the same BLAS products, hence the same rounding, as decide's.
    e = np.concatenate([chain_sums(v.counts, stack[r]) for r, v in enumerate(views)])
    q_all = np.arange(len(agents))
    # Order 0: each perspective's agent knows its own position exactly.
    e[q_all, :, agents] += ranged[owner, :, agents]
    e /= np.concatenate([v.rows for v in views])[:, None, :, None]
    # Only what a move can change is normalised per candidate: the whole root (the
    # robot's viewpoint moves, its own row does not) and, in the modelled beliefs, the
    # mover's row; every other row is the one at column 0.
    roots, mover = start[:-1], robots[owner]
    base, moved, root = e[:, 0], e[q_all, :, mover], e[roots]
    root[at, :, robots] = root[at, 0, robots][:, None]  # own motion: no own-goal evidence
    if ctrl.position_noise > 0:
        factor = noise_attenuation(
            pos, robots, ctrl.bearing, ctrl.position_noise, ctrl.eta, ctrl.eta_bearing
        )
        base *= factor[owner][:, :, None]  # (the mover's own row keeps factor 1: exact)
        root *= factor[:, None, :, None]
    log_base, log_moved, log_root = (log_softmax(x, -1) for x in (base, moved, root))
    weights = np.concatenate([v.weights for v in views])
    model, k = ctrl.model, ctrl.configurations.shape[0]
    # numpy reduces in buffers of getbufsize() elements: beyond, a lone column's sums
    # would not run as in the single call.
    small = k <= np.getbufsize() and k * R * b <= ctrl.chunk_cells
    if model.update == "bayes" and model.index.dtype == np.float64 and small:
        prior = np.stack([priors[j] for j in rows])
        G, beliefs, focals = team_terms(
            model, log_base, log_moved, log_root, start, weights, robots, batch, prior
        )
        return G[at[:, None], back], list(beliefs), focals
    # Otherwise one robot at a time, on the full (perspectives, columns, n, m) array.
    log_p = np.repeat(log_base[:, None], b, axis=1)
    log_p[q_all, :, mover] = log_moved
    log_p[roots] = log_root
    G = np.empty((R, c))
    beliefs, focals = [], []
    for r, robot in enumerate(robots.tolist()):
        terms, q, focal = model.batch_terms(
            log_p[start[r] : start[r + 1]], views[r].weights, robot, batch[r], priors[rows[r]]
        )
        G[r] = Terms(*(t[back[r]] for t in terms)).G
        beliefs.append(q)
        focals.append(focal)
    return G, beliefs, focals


def _scene_stack(ctrl, pos: np.ndarray, robots: np.ndarray, batch: np.ndarray):
    """Measurement stack ``(R, b, n, n, m)`` and range evidence ``(R, b, n, m)`` of the
    scenes where robot ``robots[r]`` stands at ``batch[r, j]`` in ``pos[r]``.

    Only the measurements a move changes are computed per candidate (of the mover from
    every viewpoint; by the mover, if it senses bearings); the rest is the scene at
    column 0. Each entry is computed by the same elementwise formula as
    :func:`~epistemica.aif.evidence._stack` on the whole scene, with the robot's own
    coincidence scale, so it equals that entry bit for bit.
    """
    R, b = batch.shape[:2]
    at, gl, bearing = np.arange(R), ctrl.goals, ctrl.bearing
    scale = np.maximum(np.abs(pos).max(axis=(1, 2)), np.abs(batch).max(axis=(1, 2)))
    scale = np.maximum(np.maximum(scale, np.abs(gl).max()), 1.0)[:, None, None]
    here, ranged_here = stack_evidence(pos, gl, bearing, ctrl.eta, ctrl.eta_bearing, scale)
    stack = np.repeat(here[:, None], b, axis=1)
    ranged = np.repeat(ranged_here[:, None], b, axis=1)
    d = np.hypot(batch[..., None, 0] - gl[:, 0], batch[..., None, 1] - gl[:, 1])
    ranged[at, :, robots] = np.exp(-d / ctrl.eta)  # (R, b, m)
    seen = np.empty(ranged.shape)  # (R, b, viewpoint, m): the mover as each one sees it
    seen[:, :, ~bearing] = ranged[at, :, robots][:, :, None]
    if bearing.any():
        ang = angle_batch(pos[:, bearing], batch[:, None], gl, scale)  # (R, nb, b, m)
        seen[:, :, bearing] = np.exp(-ang / ctrl.eta_bearing).transpose(0, 2, 1, 3)
    seen[at, :, robots] = 0.0  # nobody measures itself
    stack[at, :, :, robots] = seen
    turning = np.flatnonzero(bearing[robots])  # movers whose own bearings move with them
    if turning.size:
        who = robots[turning]
        ang = angle_batch(batch[turning], pos[turning][:, None], gl, scale[turning])
        stack[turning, :, who] = np.exp(-ang / ctrl.eta_bearing)  # (Rb, b, n, m)
        stack[turning, :, who, who] = 0.0
    return stack, ranged
