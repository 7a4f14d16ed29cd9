"""The memoised predictions behind :class:`epistemica.aif.task_planning.TaskPlanner`: the
convention every robot follows without planning, and each chain's predicted choice at each
order (with ``fetchers``, the fetches it is predicted to make).

Examples
--------
>>> convention([[2.0], [3.0]], [[1], [1]], [2]).tolist()
[0, 0]
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from epistemica.aif.task_completion import completion_times, sorted_completion

__all__ = ["Fetch", "TaskContext", "convention", "softmax"]


def convention(arrivals, knowers, needs) -> np.ndarray:
    """``(n,)`` the task each robot goes to by the shared convention (-1: none, it
    explores): coalition by coalition, the task whose ``needs`` nearest free knowers
    assemble soonest (the latest of their arrivals is earliest) gets them, until no task
    has enough free knowers.

    Parameters
    ----------
    arrivals : array_like
        ``(n, m)`` when each robot would reach each task (``inf``: never).
    knowers : array_like
        ``(n, m)`` booleans: the robot knows of the task (as whoever applies the
        convention sees it).
    needs : array_like
        ``(m,)`` robots each task needs.

    Examples
    --------
    Three robots; task 0 (needs 2) is known to robots 0 and 1, task 1 (needs 2) to all:
    robots 1 and 2 reach task 1 by step 3, robots 0 and 1 task 0 by step 5, so task 1 goes
    first, and task 0 is left with one free knower.

    >>> convention([[5, 9], [2, 3], [9, 1]], [[1, 1], [1, 1], [0, 1]], [2, 2]).tolist()
    [-1, 1, 1]
    """
    a = np.asarray(arrivals, dtype=float)
    able = np.asarray(knowers, dtype=bool) & np.isfinite(a)
    needs = np.asarray(needs, dtype=int)
    out = np.full(a.shape[0], -1)
    left = np.ones(a.shape[1], dtype=bool)
    while left.any():
        ok = able & (out < 0)[:, None] & left[None]
        times = np.sort(np.where(ok, a, np.inf), axis=0)
        latest = times[np.minimum(needs, a.shape[0]) - 1, np.arange(a.shape[1])]
        latest = np.where(left & (needs <= a.shape[0]), latest, np.inf)
        t = int(np.argmin(latest))
        if not np.isfinite(latest[t]):
            break
        chosen = np.flatnonzero(ok[:, t])
        out[chosen[np.argsort(a[chosen, t], kind="stable")[: needs[t]]]] = t
        left[t] = False
    return out


class Fetch(NamedTuple):
    """A teammate the planning robot may fetch for a task.

    Attributes
    ----------
    task, helper : int
        The task, and the teammate that does not know of it.
    arrival, helper_arrival : float
        When the robot and the helper would reach the task (intercept, then the trip).
    found : float
        The probability that the helper is where the robot expects it.
    meeting, place : float, tuple, optional
        When and where the robot meets the helper (for a rollout; NaN / None: unknown).
    """

    task: int
    helper: int
    arrival: float
    helper_arrival: float
    found: float
    meeting: float = float("nan")
    place: tuple | None = None


def softmax(G: np.ndarray, tau: float) -> np.ndarray:
    """``exp(-G / tau)`` normalised over the finite entries (uniform when none is).

    Examples
    --------
    >>> softmax(np.array([0.0, np.inf]), 1.0).tolist()
    [1.0, 0.0]
    """
    finite = np.isfinite(G)
    if not finite.any():
        return np.full(G.shape, 1.0 / G.size)
    q = np.where(finite, np.exp(-(G - G[finite].min()) / tau), 0.0)
    return q / q.sum()


class TaskContext:
    """The memoised predictions of one :meth:`TaskPlanner.plan
    <epistemica.aif.task_planning.TaskPlanner.plan>`: chain and order -> a choice
    distribution (and, with ``meetings``, the fetches it is predicted to make).

    Examples
    --------
    >>> from epistemica.aif.task_planning import TaskPlanner
    >>> context = TaskContext(TaskPlanner([1], order=1), np.array([[3.0]]), {(0,): [True]}, {})
    >>> context.costs((0,), 1).tolist()            # the task: 100 - 3 steps saved; explore
    [-97.0, -0.0]
    """

    def __init__(
        self, planner, arrivals, sets, unknown, meetings=None, waiting=None, stands=None
    ) -> None:
        self.p = planner
        self.waiting = dict(waiting or {})  # teammate -> the task it is seen waiting at
        self.stands = dict(stands or {})  # teammate -> the task a fetch takes it from
        self.meetings = meetings  # None: teammates are not predicted to fetch
        self.options: dict = {}  # (key, order) -> the agent's fetches: tasks, helpers, G, when
        self.fetched: dict = {}  # (key, order) -> its fetch probability and time per task
        self.arrivals = arrivals
        self.sets = {tuple(c): np.asarray(v, dtype=bool) for c, v in sets.items()}
        self.unknown = {tuple(c): int(v) for c, v in unknown.items()}
        self.memo: dict = {}
        self.keys: dict = {}
        m = arrivals.shape[1]
        self.twice = np.hstack([arrivals, arrivals])
        self.cols = np.arange(2 * m)
        self.ranked: dict = {}  # agent -> the arrivals sorted down each column, and how
        self.needs2 = np.tile(planner.needs, 2)
        self.fail2 = np.tile(planner.fail, 2)

    def rank(self, agent: int) -> tuple[np.ndarray, np.ndarray]:
        """``(order, sorted)`` of the arrivals, without ``agent`` (it comes ``later``
        than its arrival) then with it, sorted down each column."""
        found = self.ranked.get(agent if np.isfinite(self.p.later) else -1)
        if found is None:
            twice = self.twice
            if np.isfinite(self.p.later):
                twice = twice.copy()
                twice[agent, : twice.shape[1] // 2] += self.p.later
            order = np.argsort(twice, axis=0, kind="stable")
            found = self.ranked[agent] = (order, twice[order, self.cols])
        return found

    def _lookup(self, table: dict, chain: tuple[int, ...]):
        # A robot at order k models sets down to chains of length k, no deeper.
        for length in range(min(len(chain), max(self.p.order, 1)), 0, -1):
            found = table.get(chain[:length])
            if found is not None:
                return found
        return None

    def costs(self, chain: tuple[int, ...], order: int) -> np.ndarray:
        """``(m + 1,)`` expected free energy (time units) of each task and exploring for
        ``chain[-1]`` at ``order``."""
        p, agent = self.p, chain[-1]
        n, m = self.arrivals.shape
        open_ = self._lookup(self.sets, chain)
        unknown = self._lookup(self.unknown, chain) or 0
        G = np.full(m + 1, np.inf)
        if order == 0:  # the convention over who it knows knows of what, else explore
            knowers = np.stack(
                [open_ if j == agent else self._lookup(self.sets, (*chain, j)) for j in range(n)]
            )
            task = convention(self.arrivals, knowers, p.needs)[agent]
            G[task if task >= 0 else m] = 0.0
            return G
        presence = np.zeros((n, 2 * m))  # without the agent, then with it
        free = np.zeros((n, 2 * m))  # the probability it explores: free to be brought
        free[agent, :m] = 1.0
        for j in range(n):
            if j != agent:
                pick = self.choice((*chain, j), order - 1)
                presence[j, :m] = presence[j, m:] = pick[:m]
                free[j] = pick[m]
        presence[agent, m:] = np.isfinite(self.arrivals[agent])  # it comes if it can
        if np.isfinite(p.later):  # and, choosing otherwise, it comes later
            presence[agent, :m] = presence[agent, m:]
        if self.meetings is None:
            order_, ranked = self.rank(agent)
            pooled = free[order_, self.cols] if p.pool else None
            coming = presence[order_, self.cols]
        else:  # the teammates' predicted fetches bring two more arrivals each
            late, came = self.rows(chain, order - 1)
            twice = self.twice.copy()
            if np.isfinite(p.later):
                twice[agent, :m] += p.later
            twice = np.vstack([twice, np.hstack([late, late])])
            order_ = np.argsort(twice, axis=0, kind="stable")
            ranked = twice[order_, self.cols]
            coming = np.vstack([presence, np.hstack([came, came])])[order_, self.cols]
            spare = np.vstack([free, np.zeros((late.shape[0], 2 * m))])
            pooled = spare[order_, self.cols] if p.pool else None
        worth = None
        if p.knowers:  # no credit for coming to a task too few know of: waiting brings nobody
            enough = np.tile(self.known(chain, open_) >= p.needs, 2).astype(float)
            worth = np.broadcast_to(enough, ranked.shape)
        both = sorted_completion(ranked, coming, self.needs2, self.fail2, p.coming, worth, pooled)
        saved = both[m:] - both[:m]
        G[:m] = np.where(open_ & np.isfinite(self.arrivals[agent]), saved, np.inf)
        G[m] = -p.explore * float(p.fail.mean()) * unknown / n
        if self.meetings is not None and len(chain) > 1:
            a = np.vstack([self.arrivals, late])
            q = np.vstack([presence[:, m:], came])
            self.options[(self.key(chain), order)] = self.own_fetches(chain, open_, both[:m], a, q)
        return G

    def known(self, chain: tuple[int, ...], open_) -> np.ndarray:
        """``(m,)`` how many robots know of each task as ``chain[:-1]`` predicts
        ``chain[-1]`` takes it: itself (``open_``) and each teammate by its chain's set."""
        n = self.arrivals.shape[0]
        count = np.asarray(open_, dtype=int).copy()
        for j in range(n):
            if j != chain[-1]:
                count += self._lookup(self.sets, (*chain, j))
        return count

    def rows(self, chain: tuple[int, ...], order: int) -> tuple[np.ndarray, np.ndarray]:
        """``(2e, m)`` arrivals and presence of the pairs ``chain[-1]``'s teammates are
        predicted (at ``order``) to fetch and bring: the fetcher and the helper each, at
        the meeting's time, coming with the fetch's probability."""
        n, m = self.arrivals.shape
        late, came = [], []
        for j in range(n):
            if j != chain[-1] and order >= 1:
                q, when = self.fetching((*chain, j), order)
                if q.any():
                    late += [when, when]
                    came += [q, q]
        if not late:
            return np.zeros((0, m)), np.zeros((0, m))
        return np.array(late), np.array(came)

    def own_fetches(self, chain: tuple[int, ...], open_, without, arrivals, presence):
        """``chain[-1]``'s fetches as ``chain[:-1]`` predicts them: ``(tasks, helpers, G,
        when)``, G against not serving the task (``without``), every other robot coming
        as predicted (``arrivals``, ``presence``: rows of robots, then of fetched pairs)."""
        p, agent = self.p, chain[-1]
        n = self.arrivals.shape[0]
        tasks, helpers = [], []
        for h in range(n):
            if h != agent:
                unaware = open_ & ~self._lookup(self.sets, (*chain, h))
                unaware &= np.isfinite(self.meetings[agent, h])
                tasks += np.flatnonzero(unaware).tolist()
                helpers += [h] * int(unaware.sum())
        if not tasks:
            return None
        tasks, helpers = np.array(tasks), np.array(helpers)
        cols = np.arange(tasks.size)
        a, q = arrivals[:, tasks], presence[:, tasks]
        when = self.meetings[agent, helpers, tasks]
        a[agent], a[helpers, cols], q[agent], q[helpers, cols] = when, when, 1.0, 1.0
        brought = None
        if p.rendezvous:  # only the helper a fetch brings earns credit
            brought = np.zeros(a.shape, dtype=bool)
            brought[helpers, cols] = True
        fetched = completion_times(a, q, p.needs[tasks], p.fail[tasks], *p.rule, brought)
        return tasks, helpers, fetched - without[tasks], when

    def choice(self, chain: tuple[int, ...], order: int) -> np.ndarray:
        """``(m + 1,)`` ``chain[-1]``'s choice as ``chain[:-1]`` predicts it: a mixture of
        orders ``0 .. order``."""
        key = (self.key(chain), order)
        found = self.memo.get(key)
        if found is None and len(chain) > 1 and chain[-1] in self.waiting:
            found = self.memo[key] = self.waits(chain[-1])  # it is seen waiting: it stays
            self.fetched[key] = (np.zeros(found.size - 1), np.full(found.size - 1, np.inf))
        if found is None:
            m = self.arrivals.shape[1]
            mix, q, when = [], np.zeros(m), np.zeros(m)
            for level in range(order + 1):
                G = self.costs(chain, level)
                fetches = self.options.get((key[0], level))
                if fetches is None:
                    mix.append(softmax(G, self.p.tau))
                    continue
                tasks, _, Gf, met = fetches
                pick = softmax(np.concatenate([G, Gf]), self.p.tau)
                mix.append(pick[: m + 1])  # the rest: the probability it fetches
                np.add.at(q, tasks, pick[m + 1 :])
                np.add.at(when, tasks, pick[m + 1 :] * met)
            found = self.memo[key] = sum(mix) / len(mix)
            some = q > 0
            when = np.where(some, when / np.where(some, q, 1.0), np.inf)
            self.fetched[key] = (q / len(mix), when)
        return found

    def waits(self, robot: int) -> np.ndarray:
        """``(m + 1,)`` the choice of a teammate seen waiting at a task: that task.

        Examples
        --------
        >>> from epistemica.aif.task_planning import TaskPlanner
        >>> planner = TaskPlanner([2, 2], order=1)
        >>> context = TaskContext(planner, np.ones((2, 2)), {(0,): [True, True]}, {}, None, {1: 1})
        >>> context.choice((0, 1), 0).tolist()
        [0.0, 1.0, 0.0]
        """
        pick = np.zeros(self.arrivals.shape[1] + 1)
        pick[self.waiting[robot]] = 1.0
        return pick

    def fetching(self, chain: tuple[int, ...], order: int) -> tuple[np.ndarray, np.ndarray]:
        """``(m,)`` the probability that ``chain[-1]`` fetches a teammate for each task
        (as :meth:`choice` predicts it), and when the pair would arrive (``inf``: never)."""
        self.choice(chain, order)
        return self.fetched[(self.key(chain), order)]

    def key(self, chain: tuple[int, ...]) -> tuple:
        """What ``chain``'s predictions depend on: its last robot and what it knows, or
        the chain itself when deeper chains may have sets of their own."""
        found = self.keys.get(chain)
        if found is None:
            if len(chain) < max(self.p.order, 1):
                found = chain
            else:
                open_ = self._lookup(self.sets, chain)
                found = (open_.tobytes(), self._lookup(self.unknown, chain), chain[-1])
            self.keys[chain] = found
        return found

    def fetch_costs(self, robot: int, fetches: Sequence[Fetch]) -> np.ndarray:
        """Expected free energy (time units) of each fetch, against not serving its task."""
        n, m = self.arrivals.shape
        if not fetches:
            return np.zeros(0)
        p = self.p
        presence, free = np.zeros((n, m)), np.ones((n, m))
        for j in range(n):
            if j != robot:
                pick = self.choice((robot, j), max(p.order - 1, 0))
                presence[j], free[j] = pick[:m], pick[m]
        late = self.arrivals.copy()
        if np.isfinite(p.later):  # not fetching, it comes later
            late[robot] += p.later
            presence[robot] = 1.0
        base = self.arrivals
        if self.meetings is not None:  # the pairs teammates are predicted to fetch
            pairs, came = self.rows((robot,), max(p.order - 1, 0))
            late, base = np.vstack([late, pairs]), np.vstack([base, pairs])
            presence, free = np.vstack([presence, came]), np.vstack([free, 0 * came])
        pool = free if p.pool else None
        worth = None
        if p.knowers:  # without the fetch, a task too few know of earns no credit
            short = self.known((robot,), self.sets[(robot,)]) < p.needs
            worth = np.broadcast_to(~short, late.shape)
        without = completion_times(late, presence, p.needs, p.fail, *p.coming, worth, pool)
        tasks = np.array([f.task for f in fetches], dtype=int)
        helpers = np.array([f.helper for f in fetches], dtype=int)
        cols = np.arange(len(fetches))
        a = base[:, tasks].copy()
        q = presence[:, tasks].copy()
        a[robot], q[robot] = [f.arrival for f in fetches], 1.0
        a[helpers, cols] = [f.helper_arrival for f in fetches]
        q[helpers, cols] = [f.found for f in fetches]
        brought = None
        if p.rendezvous:  # only the helper a fetch brings earns credit
            brought = np.zeros(a.shape, dtype=bool)
            brought[helpers, cols] = True
        if p.pool:
            pool = free[:, tasks].copy()
            pool[robot], pool[helpers, cols] = 0.0, 1.0 - q[helpers, cols]
        fetched = completion_times(a, q, p.needs[tasks], p.fail[tasks], *p.rule, brought, pool)
        return fetched - without[tasks] + self.taken(late, presence, without, fetches)

    def taken(self, late, presence, without, fetches: Sequence[Fetch]) -> np.ndarray:
        """What each fetch costs the other tasks (time units): its helper, brought to the
        fetch's task, no longer comes to those it was predicted to (``mission``), or, a
        helper seen standing at a task (``stands``), to that one; else 0."""
        cost = np.zeros(len(fetches))
        if not (self.p.mission or self.stands):
            return cost
        lost = {}
        for k, f in enumerate(fetches):
            there = self.stands.get(f.helper, f.task)
            if not self.p.mission and there == f.task:
                continue
            if f.helper not in lost:
                q = presence.copy()
                q[f.helper] = 0.0
                p = self.p
                lost[f.helper] = completion_times(late, q, p.needs, p.fail, *p.coming) - without
            gone = lost[f.helper]
            cost[k] = f.found * (gone.sum() - gone[f.task] if self.p.mission else gone[there])
        return cost
