"""The planner's waiting option: what waiting ``h`` steps, then choosing, is worth.

Waiting is valued by what it reveals (aif.md §6g, "Epistemic value"): over particles of
the teammates' true goals, each teammate that moves raises the robot's evidence for its
goal, and the robot then heads for the goal of least expected time under the revised
predictions. ``Planner(waiting=)`` picks how teammates are modelled while it waits:

- 0: each reveals its goal at the speed it was seen to use (session 52's model). Two
  robots that each expect the other to reveal both wait; one that is not the bottleneck
  waits for free.
- 1: each teammate's revelation is weighted by the probability that it moves rather than
  waits, predicted one order down (:func:`movers`: "what I think you will do").
- 2: in each particle a teammate waits with that probability: it reveals nothing and
  arrives ``h`` steps later (a particle where nobody moves reveals nothing and costs time).
- 3: waiting is priced against heading now on the same particles, so that only the value
  of the information and the time it costs separate the two; the estimator's own error
  (particles against the analytic risk) and the tie-breaks no longer favour waiting.
- 4: the moves are read with noise: ``g`` nats of evidence for the true goal come with
  ``sqrt(g)`` nats of noise on every goal (a Gaussian reading: log-odds of the truth
  against another goal ``N(g, 2g)``), so a glimpse no longer reveals a goal for certain:
  in a near tie the faintest evidence decided the particle's choice rightly.
- 5: only the teammates in sight now reveal anything (sight is mutual: ``watching``); one
  out of sight was taken to reveal its goal at full speed to a robot that cannot see it.
- 6: the moves are read as the planner reads them (``motion_evidence``: each step the step
  towards the goal plus Gaussian error ``sigma``), not at the position's rate ``v / eta``
  (2 s at 1 m/s over eta = 50 m: 0.04 nats, where a step 90 degrees off the goal with
  ``sigma`` 0.5 m costs 4 nats).
- 7: each particle's outcome is scored by its posterior probability that the choice
  completes a configuration (and the time it would), not by whether its one draw of the
  teammates' goals matched: from 4 on the revised predictions are the posterior given the
  particle's reading, so this is the same expectation with far less variance. With 32
  particles over 24 configurations, few or none matched, and ``-ln`` of that share is the
  success term: an estimate of 0 costs 27.6 nats, and waiting was priced tens of nats
  below heading for nothing.
- 8: waiting is priced against heading for a goal for as many steps and then choosing
  again with what the same particles revealed, not against heading now for good: the
  planner plans again every step, so a robot that heads off reads its teammates' moves
  too, and waiting pays only where standing keeps it nearer the goal it will take. A
  gain under :data:`TIE` goes to heading (equal options were decided by rounding).

Internal to the planner (:class:`epistemica.aif.planning.Planner`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from epistemica.aif.plan_context import quasi_uniform
from epistemica.del_.errors import InvalidArgumentError

if TYPE_CHECKING:  # the planner passes its contexts; only the type is named here
    from epistemica.aif.plan_context import PlanContext

__all__ = ["driven", "model", "movers", "priced", "wait_cost", "waiting"]

#: The waiting models ``Planner(waiting=)`` knows (the module docstring).
MODELS = (0, 1, 2, 3, 4, 5, 6, 7, 8)
#: Seconds under which waiting's gain is a tie (model 8), which goes to heading: with
#: nothing revealed the two options are equal, and rounding chose waiting half the time.
TIE = 1e-6
#: Standard normal draws of the moves' reading noise (``waiting >= 4``): one fixed table,
#: so a plan stays a deterministic function of what the robot observes.
NOISE = np.random.default_rng(37).standard_normal((256, 16, 16))


def model(value) -> int:
    """``value`` checked as one of :data:`MODELS`."""
    if isinstance(value, bool) or value not in MODELS:
        raise InvalidArgumentError(
            f"waiting must be one of {MODELS}, got {value!r}", hint="8 (default); 0 uncorrected"
        )
    return int(value)


def wait_cost(context: PlanContext, robot: int, preds, moving, G: np.ndarray,
              watching=None) -> float:  # fmt: skip
    """``G(wait)`` (s) of ``robot`` under the planner's waiting model; ``G`` its goals',
    ``watching`` (``(n,)`` booleans) who sees it now; ``inf`` where no waiting is planned
    (horizon 1, order 0, a robot alone)."""
    p = context.p
    if p.horizon <= 1 or p.order < 1 or preds.shape[0] < 2:
        return np.inf
    move = movers(context, robot, moving) if p.waiting >= 1 else None
    if p.waiting >= 5 and watching is not None:  # one out of sight reveals nothing to it
        moving = np.where(np.asarray(watching, dtype=bool), moving, 0.0)
    return priced(context, (robot,), preds, moving, move, G)


def priced(context: PlanContext, chain, preds, moving, move, G: np.ndarray) -> float:
    """``chain[-1]``'s ``G(wait)`` (s): its :func:`waiting`, from model 3 on against
    heading now on the same particles (``G``'s best plus the difference), from model 8 on
    against heading for a goal for as long and then choosing again."""
    p = context.p
    finite = np.flatnonzero(np.isfinite(G))
    if p.waiting < 8 or not finite.size:
        wait = waiting(context, chain, preds, moving, move)
        if p.waiting < 3 or not finite.size:
            return wait
        return float(G[finite].min()) + wait - waiting(context, chain, preds, moving, move, 0.0)
    drawn = _particles(context, chain, preds, moving, move)  # one draw for every option
    wait = _waited(context, chain, drawn)
    heads = [_waited(context, chain, drawn, driven(context, chain[-1], g)) for g in finite]
    gain = min(heads) - wait
    if gain > TIE:
        return float(G[finite].min()) - gain
    return float(G[finite].min()) + max(-gain, TIE)  # a tie goes to heading


def driven(context: PlanContext, robot: int, goal: int) -> np.ndarray:
    """``(m,)`` the robot's time (s) to each goal after driving ``horizon - 1`` steps
    towards ``goal`` (or reaching it), those steps included."""
    p = context.p
    delay = (p.horizon - 1) * p.dt
    here = context.pos[robot]
    to = p.goals[goal] - here
    far = float(np.hypot(*to))
    there = here + to * min(1.0, delay * p.speeds[robot] / far) if far > 0 else here
    return np.hypot(*(p.goals - there).T) / p.speeds[robot] + delay


def movers(context: PlanContext, robot: int, moving) -> np.ndarray:
    """``(n,)`` the probability that each teammate moves rather than waits: predicted
    one order down, choosing among its goals and waiting by the softmax of ``-G / tau``
    its goals' prediction uses, its own teammates taken to move (the recursion stops
    there). 1 below order 2 (order 0 never waits) and for a typed teammate (no planner).

    Examples
    --------
    Two robots side by side midway between two goals to share, a mismatch dear; the
    teammate (order 1) expects the robot to reveal its goal by moving, so it waits:

    >>> from epistemica.aif.planning import Planner
    >>> from epistemica.aif.plan_context import PlanContext
    >>> planner = Planner([[0.0, 0.0], [10.0, 0.0]], [[0, 1], [1, 0]], [1.0, 1.0], order=2,
    ...                   horizon=3, waiting=1, evidence=0.2, repair=3.0, success_weight=0)
    >>> context = PlanContext(planner, np.array([[5.0, 0.0], [5.0, 0.1]]), np.ones(2), {})
    >>> movers(context, 0, np.ones(2)).round(3).tolist()
    [1.0, 0.011]
    """
    p = context.p
    n, below = p.speeds.shape[0], p.order - 1
    move = np.ones(n)
    for other in range(n) if below >= 1 else ():
        chain = (robot, other)
        if other == robot or other in context.typed:
            continue
        G = context.costs(chain, below)
        G = G[np.isfinite(G)]
        if not G.size:
            continue
        # Its plan's rows: its own choice, and each of its teammates one order below it.
        rows = [context.choice(chain if j == other else (*chain, j), below - (j != other))
                for j in range(n)]  # fmt: skip
        preds = np.stack(rows)
        wait = priced(context, chain, preds, moving, None, context.costs(chain, below))
        low = min(G.min(), wait)
        heads = np.exp(-(G - low) / p.tau).sum()
        move[other] = heads / (heads + np.exp(-(wait - low) / p.tau))
    return move


def waiting(context: PlanContext, chain: tuple[int, ...], preds: np.ndarray, moving,
            move=None, delay: float | None = None, own=None) -> float:  # fmt: skip
    """Expected completion time (s) of ``chain[-1]`` waiting ``horizon`` steps (or
    ``delay`` s), then choosing, over the set of ``chain``. ``move`` (``(n,)``): the
    probability that each teammate moves (:func:`movers`; default 1); with ``waiting >= 2``
    who waits is drawn per particle: a waiter reveals nothing and arrives ``delay`` later.
    ``own``: its times to the goals after those steps (default: it stands, ``+ delay``)."""
    drawn = _particles(context, chain, preds, moving, move, delay)
    return _waited(context, chain, drawn, own)


def _particles(context: PlanContext, chain, preds, moving, move=None, delay=None) -> tuple:
    """What :func:`waiting` draws before the robot's own times enter: the rows of
    ``chain``'s set, the particles' revised predictions and true goals, the teammates'
    latest arrival in each (``(P, k')``), and the delay (shared by every option priced)."""
    p, robot = context.p, chain[-1]
    n, m = preds.shape
    mask = context.mask(chain)
    rows = p.configurations if mask is None else p.configurations[mask]
    times = context.row_times if mask is None else context.row_times[mask]
    delay = (p.horizon - 1) * p.dt if delay is None else delay
    others = np.array([j for j in range(n) if j != robot])
    # Particles of the teammates' true goals, and what waiting reveals of them.
    cumulative = np.cumsum(preds[others], axis=1)
    draws = quasi_uniform(p.particles, (2 if p.waiting >= 2 else 1) * others.size)
    truth = np.minimum((draws[:, : others.size, None] > cumulative[None]).sum(axis=2), m - 1)
    move = np.ones(n) if move is None else np.asarray(move, dtype=float)
    stays = np.zeros((p.particles, others.size), dtype=bool)  # (P, n - 1): who waits
    if p.waiting >= 2:
        stays = draws[:, others.size :] >= move[others][None]
    share = np.where(stays, 0.0, 1.0 if p.waiting >= 2 else move[others][None])
    share = share * np.asarray(moving, dtype=float)[others][None]  # (P, n - 1)
    revised = np.log(np.maximum(preds[others], 1e-300))[None] + _revealed(
        context, others, truth, share, delay
    )
    revised = np.exp(revised - revised.max(axis=2, keepdims=True))
    revised /= revised.sum(axis=2, keepdims=True)
    late = (times[None][..., others] + delay * stays[:, None, :]).max(axis=2)  # (P, k')
    return rows, revised, truth, late, delay


def _waited(context: PlanContext, chain, drawn: tuple, own=None) -> float:
    """:func:`waiting` on the particles ``drawn`` (:func:`_particles`), the robot's times
    to the goals ``own`` (default: it stands, ``+ delay``)."""
    robot = chain[-1]
    rows, revised, truth, late, delay = drawn
    own_time = context.times[robot] + delay if own is None else own
    finish = np.maximum(late, own_time[rows[:, robot]][None])  # (P, k')
    return _realised(context.p, robot, rows, (revised, truth, finish), own_time)


def _revealed(context: PlanContext, others, truth, share, delay: float) -> np.ndarray:
    """``(P, n - 1, m)`` the log-likelihood of each goal of each teammate after ``delay``
    s of its moves towards its particle's ``truth`` at ``share`` of its speed."""
    p = context.p
    P, m = truth.shape[0], p.goals.shape[0]
    if p.waiting < 6:  # the position's evidence, gain = delay v / eta nats for the truth
        gain = delay * p.speeds[others][None] * share / p.eta  # (P, n - 1)
        out = np.zeros((P, others.size, m))
        np.put_along_axis(out, truth[..., None], gain[..., None], axis=2)
        if p.waiting >= 4:  # read with noise: log-odds truth : other ~ N(gain, 2 gain)
            out = out + np.sqrt(gain)[..., None] * NOISE[:P, : others.size, :m]
        return out
    # Read as the planner reads moves (motion_evidence): each step is the step towards the
    # goal plus Gaussian error sigma, so ``S`` steps are one mean step of error sigma / √S.
    steps = round(delay / p.dt)
    if steps == 0:
        return np.zeros((P, others.size, m))
    to = p.goals[None] - context.pos[others][:, None]  # (n - 1, m, 2)
    far = np.maximum(np.hypot(to[..., 0], to[..., 1]), 1e-9)
    reach = (p.speeds[others] * p.dt)[:, None]
    step = to * (np.minimum(reach, far) / far)[..., None]  # (n - 1, m, 2) towards each goal
    made = step[np.arange(others.size)[None], truth] * share[..., None]  # (P, n - 1, 2)
    made = made + p.sigma / np.sqrt(steps) * NOISE[:P, : others.size, :2]
    residual = made[:, :, None, :] - step[None]  # (P, n - 1, m, 2)
    read = -steps * (residual**2).sum(axis=3) / (2 * p.sigma**2)
    return np.where(share[..., None] > 0, read, 0.0)  # who stands or is out of sight: none


def _realised(p, robot: int, rows: np.ndarray, particles, own_time: np.ndarray) -> float:
    """The risk (s) of choosing, in each particle, the goal of least expected time under
    its revised predictions, realised against its true goals (``particles``: revised
    ``(P, n - 1, m)``, truth ``(P, n - 1)``, finish ``(P, k')``)."""
    revised, truth, finish = particles
    m = own_time.shape[0]
    others = np.array([j for j in range(rows.shape[1]) if j != robot])
    w = np.prod(revised[:, np.arange(others.size), rows[:, others]], axis=2)  # (P, k')
    slot = rows[:, robot][None] + m * np.arange(p.particles)[:, None]
    valid = np.bincount(slot.ravel(), weights=w.ravel(), minlength=m * p.particles)
    timed = np.bincount(slot.ravel(), (w * finish).ravel(), minlength=m * p.particles)
    expected = p.risk(valid, timed, np.tile(own_time, p.particles)).reshape(p.particles, m)
    options = np.bincount(rows[:, robot], minlength=m) > 0
    chosen = np.argmin(np.where(options[None], expected, np.inf), axis=1)  # (P,)
    if p.waiting >= 7:  # each particle's posterior odds that the choice forms, not its draw
        pick = chosen + m * np.arange(p.particles)
        formed, timed, alone = valid[pick], timed[pick], own_time[chosen]
        if p.success_weight > 0:
            return float(p.risk(formed.mean()[None], timed.mean()[None], alone.mean()[None])[0])
        return float((timed + (1.0 - formed) * (alone + p.repair)).mean())
    # Realised: does the chosen goal complete the particle's configuration?
    match = (rows[None, :, others] == truth[:, None, :]).all(axis=2)
    match &= rows[None, :, robot] == chosen[:, None]
    done = np.where(match, finish, np.inf).min(axis=1)
    formed = np.isfinite(done)
    share = formed.mean()
    if p.success_weight > 0:  # the same risk, estimated from the particles
        timed = done[formed].sum() if formed.any() else 0.0
        return float(p.risk(np.array([share]), np.array([timed / p.particles]),
                            np.array([own_time[chosen].mean()]))[0])  # fmt: skip
    return float(np.where(formed, done, own_time[chosen] + p.repair).mean())
