"""Planning by expected free energy for tasks that need several robots at once.

A robot of a joint (collaborative) mission chooses among *options*: go to a task it knows
is open, fetch a teammate it knows does not know of a task (meet it, then bring it), or
explore for the tasks it does not know of yet. The preference over outcomes is exponential
in the sum of the tasks' completion times (``ln C = -sum_t T_t / tau``), so the risk term
of an option's expected free energy is the expected sum of completion times in units of
the precision ``tau``; the robot's option changes only the term of the task it serves, so

    G(go t) = ( E[T_t | it goes] - E[T_t | it does not] ) / tau

a (negative) expected time saved. A task is done at the ``needs[t]``-th arrival among the
robots that come; with each teammate ``l`` coming with its predicted probability
``pi_l(t)`` (independently), ``E[T_t]`` is exact (:func:`completion_times`), and a task
that too few robots come to costs ``fail`` (the time until someone else happens by).
Fetching teammate ``j`` for ``t`` is the same with ``j`` arriving after the intercept and
the trip back, found with the probability the robot gives it. Exploring saves
``explore * fail`` per task still unknown, shared among the team.

The predictions are where the order of reasoning enters, as in
:mod:`epistemica.aif.planning`: at order ``k`` a robot predicts each teammate ``l`` as
choosing by the same expected free energy at orders ``0 .. k - 1`` (a cognitive hierarchy)
over the tasks the robot knows ``l`` knows of (the chain ``(i, l)``), and ``l``'s own
predictions over the chains ``(i, l, j)``, down to order 0: the convention every robot
follows without planning (:func:`convention`: coalition by coalition, the task whose
knowers assemble soonest gets them; a robot left out explores).

Examples
--------
Two robots, one task needing both, 5 and 10 steps away; each knows the other knows of it:

>>> import numpy as np
>>> planner = TaskPlanner([2], order=1, temperature=1.0, fail=[100.0])
>>> plan = planner.plan(0, [[5.0], [10.0]], {(0,): [True]})
>>> plan.kind, plan.task, float(plan.G[0])          # 10 steps instead of the 100 of failing
('task', 0, -90.0)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np

from epistemica.aif._validate import as_finite, positive
from epistemica.aif.evidence import check_order, check_robot
from epistemica.aif.task_completion import Credit, completion_times, sorted_completion
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["Fetch", "TaskPlan", "TaskPlanner", "completion_times", "convention"]


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
    """

    task: int
    helper: int
    arrival: float
    helper_arrival: float
    found: float


class TaskPlan(NamedTuple):
    """One robot's plan at one step.

    Attributes
    ----------
    kind : str
        ``"task"``, ``"fetch"`` or ``"explore"``.
    task, helper : int
        The task it serves (-1 exploring) and the teammate it fetches (-1 none).
    option : int
        The chosen index of ``G``: tasks ``0 .. m-1``, exploring ``m``, then the fetches
        in the order given.
    G : numpy.ndarray
        Expected free energy of every option (nats; ``inf`` where it is no option).
    predictions : numpy.ndarray
        ``(n, m + 1)`` every robot's predicted choice of a task or exploring (its own
        row: ``softmax(-G)`` over tasks and exploring).
    """

    kind: str
    task: int
    helper: int
    option: int
    G: np.ndarray
    predictions: np.ndarray


class TaskPlanner:
    """Expected-free-energy planning over tasks at an order of reasoning.

    Parameters
    ----------
    needs : sequence of int
        Robots each task needs at once.
    order : {0, 1, 2, 3}
        Order of reasoning; 0 follows the convention (:func:`convention`) without
        predicting anyone (the prior's mode: the ablation of planning).
    temperature : float
        The precision ``tau``, in the units of the arrival times.
    fail : array_like
        ``(m,)`` the cost of a task too few robots come to.
    explore : float
        Time saved per unknown task by one more explorer, as a fraction of the mean
        ``fail`` divided by the team's size.
    commitment : float
        Nats a robot pays to change the option it chose at its last plan.
    convention : float
        Weight of the convention's choice for the robot (order 0, :func:`convention`) in
        its own choice (``- convention * ln p0(option)`` nats, ``p0`` the convention's
        choice with 5 % spread over every option): the shared tie-break that resolves
        standoffs the same way for every robot.
    credit : float
        :func:`completion_times`' credit for the robots that come to a task too few come
        to (0: all or nothing).
    recruit : bool
        The convention's prior gives every fetch the weight it gives exploring (the
        convention never fetches: it leaves a robot that no task has room for free to
        explore, or to spend that time telling a teammate), rather than its 5 % spread.
    timed, quorum :
        :func:`completion_times`' credit rules (timed: fetches rank by meeting time).
    later : float
        Choosing otherwise, the robot still comes to a task this much later: an option is
        worth the time by which it comes sooner. ``inf``: it never comes.
    rendezvous : bool
        Going to a task is worth the completion its coming makes more likely given the
        teammates' predicted choices (done at the ``needs``-th arrival, not at all when too
        few come); ``credit`` goes only to a teammate a fetch brings (a knower gained),
        not to robots that come to a short-handed task of their own accord.
    mission : bool
        A fetch is charged what its helper's other tasks lose: brought to the fetch's
        task, it no longer comes to those it was predicted to (the preference is over the
        sum of the tasks' completion times, and a fetch changes more than one term).
    pool : bool
        Credit for the robots at a short-handed task counts only when enough of the rest
        are predicted free (exploring) to make up the number: waiting for teammates
        predicted at other tasks is worth nothing (:func:`completion_times`' ``free``).
    """

    def __init__(
        self,
        needs: Sequence[int],
        *,
        order: int = 3,
        temperature: float = 10.0,
        fail=100.0,
        explore: float = 0.25,
        commitment: float = 0.0,
        convention: float = 0.0,
        credit: float = 0.0,
        recruit: bool = False,
        timed: bool = False,
        quorum: int = 1,
        later: float = np.inf,
        rendezvous: bool = False,
        mission: bool = False,
        pool: bool = False,
    ) -> None:
        self.needs = np.asarray(needs, dtype=int)
        m = self.needs.shape[0]
        if m == 0 or np.any(self.needs < 1):
            raise InvalidArgumentError("need at least one task, each needing >= 1 robot")
        self.order = check_order(order)
        self.tau = positive(temperature, "temperature")
        self.fail = np.broadcast_to(as_finite(fail, "fail"), (m,)).astype(float)
        self.explore = float(as_finite(explore, "explore"))
        self.commitment = float(as_finite(commitment, "commitment"))
        self.convention = float(as_finite(convention, "convention"))
        self.credit = float(np.clip(as_finite(credit, "credit"), 0.0, 1.0))
        self.recruit = bool(recruit)
        if int(quorum) < 1:
            raise InvalidArgumentError(f"quorum must be >= 1, got {quorum}")
        self.rule = Credit(self.credit, bool(timed), int(quorum))
        self.rendezvous = bool(rendezvous)  # no credit for coming: only for bringing
        self.coming = self.rule._replace(share=0.0) if rendezvous else self.rule
        self.mission = bool(mission)
        self.pool = bool(pool)
        self.later = float(later)
        if not self.later > 0:
            raise InvalidArgumentError(f"later must be > 0 (inf: never), got {later}")
        if min(self.explore, self.commitment, self.convention) < 0 or np.any(self.fail <= 0):
            raise InvalidArgumentError(
                "explore and commitment must be >= 0 and fail > 0", hint="0 leaves them out"
            )

    def plan(
        self,
        robot: int,
        arrivals,
        sets: Mapping[tuple[int, ...], Sequence[bool]],
        unknown: Mapping[tuple[int, ...], int] | None = None,
        fetches: Sequence[Fetch] = (),
        previous: int | None = None,
    ) -> TaskPlan:
        """Robot ``robot``'s plan.

        Parameters
        ----------
        robot : int
            The planning robot.
        arrivals : array_like
            ``(n, m)`` when each robot would reach each task as it predicts (``inf``: never).
        sets : mapping
            Chain ``(robot, l, ...)`` -> ``(m,)`` the open tasks the robot knows the last
            robot of the chain knows of, as the middle robots see it (a chain without an
            entry takes its longest prefix that has one; ``(robot,)`` is required).
        unknown : mapping, optional
            Chain -> how many tasks its last robot knows nothing of (same fallback; 0).
        fetches : sequence of Fetch
            The teammates it may fetch.
        previous : int, optional
            Its last plan's option (an index of :attr:`TaskPlan.G`).

        Examples
        --------
        The same two robots, robot 1 not knowing of the task; robot 0 meets it in 4 steps
        and both reach the task 12 steps from now; it finds it with probability 0.9:

        >>> planner = TaskPlanner([2], order=2, temperature=1.0, fail=[100.0])
        >>> sets = {(0,): [True], (0, 1): [False]}
        >>> plan = planner.plan(0, [[5.0], [10.0]], sets, {(0, 1): 1},
        ...                     [Fetch(0, 1, 12.0, 12.0, 0.9)])
        >>> plan.kind, plan.helper, round(float(plan.G[2]), 6)   # 0.9 * 12 + 0.1 * 100 - 100
        ('fetch', 1, -79.2)
        """
        a = np.asarray(arrivals, dtype=float)
        n, m = a.shape[0], self.needs.shape[0]
        robot = check_robot(robot, n)
        if a.shape != (n, m) or np.isnan(a).any():
            raise InvalidArgumentError(f"arrivals must be ({n}, {m}) numbers, got {a.shape}")
        if (robot,) not in sets:
            raise InvalidArgumentError("sets needs the robot's own chain", hint="(robot,)")
        context = _Context(self, a, sets, unknown or {})
        own = context.costs((robot,), self.order)
        fetching = self.order >= 1 and n > 1
        extra = context.fetch_costs(robot, fetches) if fetching else np.full(len(fetches), np.inf)
        G = np.concatenate([own, extra])
        if self.convention > 0 and self.order >= 1:  # the shared convention breaks standoffs
            prior = np.full(G.size, 0.05 / G.size)
            prior[: m + 1] += 0.95 * _softmax(context.costs((robot,), 0), self.tau)
            if self.recruit:  # a fetch is as likely as exploring (the convention's free time)
                prior[m + 1 :] = prior[m]
            G = G - self.convention * self.tau * np.log(prior)
        if previous is not None and 0 <= previous < G.size and np.isfinite(G[previous]):
            G = G + self.commitment * self.tau
            G[previous] -= self.commitment * self.tau
        best = int(np.argmin(G))
        if G[m] <= G[best] + 1e-9 * self.tau:  # nothing saves more: explore (ties too)
            best = m
        preds = np.stack(
            [
                _softmax(own, self.tau) if j == robot
                else context.choice((robot, j), max(self.order - 1, 0))
                for j in range(n)
            ]
        )  # fmt: skip
        if best < m:
            kind, task, helper = "task", best, -1
        elif best == m:
            kind, task, helper = "explore", -1, -1
        else:
            fetch = fetches[best - m - 1]
            kind, task, helper = "fetch", int(fetch.task), int(fetch.helper)
        return TaskPlan(kind, task, helper, best, G / self.tau, preds)


def _softmax(G: np.ndarray, tau: float) -> np.ndarray:
    finite = np.isfinite(G)
    if not finite.any():
        return np.full(G.shape, 1.0 / G.size)
    q = np.where(finite, np.exp(-(G - G[finite].min()) / tau), 0.0)
    return q / q.sum()


class _Context:
    """The memoised predictions of one plan: chain and order -> a choice distribution."""

    def __init__(self, planner: TaskPlanner, arrivals, sets, unknown) -> None:
        self.p = planner
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
        order_, ranked = self.rank(agent)
        pooled = free[order_, self.cols] if p.pool else None
        coming = presence[order_, self.cols]
        both = sorted_completion(ranked, coming, self.needs2, self.fail2, p.coming, free=pooled)
        saved = both[m:] - both[:m]
        G[:m] = np.where(open_ & np.isfinite(self.arrivals[agent]), saved, np.inf)
        G[m] = -p.explore * float(p.fail.mean()) * unknown / n
        return G

    def choice(self, chain: tuple[int, ...], order: int) -> np.ndarray:
        """``(m + 1,)`` ``chain[-1]``'s choice as ``chain[:-1]`` predicts it: a mixture of
        orders ``0 .. order``."""
        key = (self.key(chain), order)
        found = self.memo.get(key)
        if found is None:
            mix = [_softmax(self.costs(chain, level), self.p.tau) for level in range(order + 1)]
            found = self.memo[key] = sum(mix) / len(mix)
        return found

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
        pool = free if p.pool else None
        without = completion_times(late, presence, p.needs, p.fail, *p.coming, free=pool)
        tasks = np.array([f.task for f in fetches], dtype=int)
        helpers = np.array([f.helper for f in fetches], dtype=int)
        cols = np.arange(len(fetches))
        a = self.arrivals[:, tasks].copy()
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
        fetch's task, no longer comes to those it was predicted to (``mission``; else 0)."""
        cost = np.zeros(len(fetches))
        if not self.p.mission:
            return cost
        lost = {}
        for k, f in enumerate(fetches):
            if f.helper not in lost:
                q = presence.copy()
                q[f.helper] = 0.0
                p = self.p
                lost[f.helper] = completion_times(late, q, p.needs, p.fail, *p.coming) - without
            cost[k] = f.found * (lost[f.helper].sum() - lost[f.helper][f.task])
        return cost
