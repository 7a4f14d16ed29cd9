"""Rollout valuation of a robot's options in a collaborative mission: chains of fetches.

The one-step valuation of :mod:`epistemica.aif.task_planning` prices an option by the
task it serves alone, so a task that must be recruited for over *several* fetches (robot
3 alone knows of a task needing three; fetching robot 1 pays only because robot 1, once
fetched, fetches the next) is worth nothing to it. Here each option is valued by policy
improvement by rollout (Bertsekas): robot ``i`` commits to the option for its first leg,
and then every robot, ``i`` included, follows a *base policy* in an abstract,
event-driven model of the team over ``i``'s beliefs until every task it knows of is done,
or a ``horizon`` has passed. The option's value is the sum of the tasks' completion times
(``horizon`` for a task not done by then): the risk term of a multi-step expected free
energy with the base policy for the tail.

The model: robots move in straight lines at their speed; a robot that is not going
anywhere stands still (where its teammates find it). The base policy of a free robot, on
what it knows: the convention (:func:`~epistemica.aif.task_context.convention`) over the
free robots it thinks know of each task, for the robots each task still needs (robots
already going there are seen by all); else, for a task it knows still needs robots, the
free knower and the free robot that does not know of it nearest each other (as it sees
them) are fetcher and fetched: it fetches if it is that fetcher, else goes to the task to
wait. A fetched robot learns every task its fetcher knows of (and may fetch in turn);
robots going to a task learn nothing else. A task is done at the ``needs``-th arrival of
the robots going there, which are then free at the task. The teammates' first moves are
decided before robot ``i``'s, counting it free: they do not see its choice.

What robot ``j`` knows starts as robot ``i`` thinks it does (the chain ``(i, j)``); what
``j`` thinks ``l`` knows is the chain ``(i, j, l)`` at order 3 and ``(i, l)`` below (every
robot then shares ``i``'s picture, fetches included). ``mixed`` averages the rollouts of
orders 2 to ``order``, as the one-step predictions mix orders: the third-order sets lag
(a teammate's news of a third robot reaches the ledger late), and a rollout that trusted
them alone sent a robot to a task its waiting teammates were not at.

Examples
--------
Robot 0 alone knows of a task needing three, at its feet; robots 1 and 2 stand 10 and 20
metres along a line. Going to the task saves nothing (nobody else ever learns of it);
fetching robot 1 makes a chain (robot 0 then fetches robot 2 while robot 1 goes to wait;
all three are at the task at step 40, against the horizon's 100), and so does fetching
robot 2 first:

>>> geometry = Geometry([[0.0, 0.0], [10.0, 0.0], [20.0, 0.0]], [[0.0, 0.0]], [1.0] * 3)
>>> sets = {(0,): [True], (0, 1): [False], (0, 2): [False]}
>>> go, fetch = rollout_values(0, geometry, sets, [3], 100.0, 2, [1, 2])
>>> go.tolist(), fetch.tolist()
([0.0], [-60.0, -60.0])
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np

from epistemica.aif._validate import positive
from epistemica.aif.task_context import convention
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["Geometry", "Leg", "rollout_total", "rollout_values", "team_views"]

FREE, GOING, FETCHING, HELD, ABSENT = range(5)


class Geometry(NamedTuple):
    """Where the robots and tasks are, as the planning robot predicts.

    Attributes
    ----------
    positions : array_like
        ``(n, 2)`` robots' positions, or ``(p, n, 2)`` particles of them (values are
        averaged over the particles).
    tasks : array_like
        ``(m, 2)`` the tasks' positions.
    speed : array_like
        ``(n,)`` distance each robot covers per time unit.
    """

    positions: np.ndarray
    tasks: np.ndarray
    speed: np.ndarray


class Leg(NamedTuple):
    """The planning robot's first leg: ``kind`` is ``"task"`` (``target`` a task),
    ``"fetch"`` (``target`` a teammate) or ``"absent"`` (it takes no part). A fetch meets
    the teammate at time ``when`` at ``place`` if they are given (an intercept on its
    predicted path), else where it stands.

    Examples
    --------
    >>> Leg("fetch", 2).target
    2
    """

    kind: str
    target: int = -1
    when: float = float("nan")
    place: tuple | None = None


def _lookup(sets: Mapping, chain: tuple[int, ...], fallback: np.ndarray) -> np.ndarray:
    found = sets.get(chain)
    return fallback if found is None else np.asarray(found, dtype=bool)


def team_views(robot: int, n: int, sets: Mapping, order: int) -> tuple[np.ndarray, np.ndarray]:
    """``(K, V)``: ``K[j]`` the tasks robot ``j`` knows of and ``V[j, l]`` those ``j``
    thinks ``l`` knows of, as ``robot`` starts its rollout (``V[j, j] = K[j]``).

    Parameters
    ----------
    robot, n : int
        The planning robot, and the team's size.
    sets : mapping
        Chain -> ``(m,)`` booleans, as :meth:`TaskPlanner.plan
        <epistemica.aif.task_planning.TaskPlanner.plan>` takes them (``(robot,)``
        required; a missing ``(robot, j)`` falls back to ``(robot,)``, a missing
        ``(robot, j, l)`` to ``(robot, l)``).
    order : int
        Order of reasoning: at 3 ``V[j, l]`` is the chain ``(robot, j, l)``, below it
        ``K[l]``.

    Examples
    --------
    >>> K, V = team_views(0, 2, {(0,): [True, True], (0, 1): [True, False],
    ...                          (0, 1, 0): [True, False]}, 3)
    >>> K.tolist(), V[1].tolist()
    ([[True, True], [True, False]], [[True, False], [True, False]])
    """
    own = np.asarray(sets[(robot,)], dtype=bool)
    K = np.stack([own if j == robot else _lookup(sets, (robot, j), own) & own for j in range(n)])
    V = np.broadcast_to(K, (n, *K.shape)).copy()
    if order >= 3:
        for j in range(n):
            for k in range(n):
                if j != robot and k != j:
                    V[j, k] = _lookup(sets, (robot, j, k), K[k]) & own
    return K, V


class _Team:
    """The abstract team of one rollout: who is where, doing what, knowing what."""

    def __init__(self, positions, geometry: Geometry, needs, K, V, shared: bool) -> None:
        self.pos = np.array(positions, dtype=float)
        self.tasks = np.asarray(geometry.tasks, dtype=float)
        self.speed = np.asarray(geometry.speed, dtype=float)
        self.needs = needs
        self.K, self.V, self.shared = K.copy(), V.copy(), shared
        n, m = K.shape
        self.status = np.full(n, FREE)
        self.goal = np.full(n, -1)  # the task going to, or the teammate fetching
        self.when = np.full(n, np.inf)  # arrival at the task, or the meeting
        self.done = ~K.any(axis=0)  # tasks nobody knows of are out of the rollout
        self.done_at = np.zeros(m)

    def start(self, robot: int, leg: Leg) -> None:
        """The planning robot's first leg, from time 0."""
        if leg.kind == "absent":
            self.status[robot] = ABSENT
        elif leg.kind == "task":
            gap = np.hypot(*(self.tasks[leg.target] - self.pos[robot]))
            self.status[robot], self.goal[robot] = GOING, leg.target
            self.when[robot] = gap / self.speed[robot]
        else:
            self._fetch(robot, leg.target, 0.0)
            if leg.place is not None and np.isfinite(leg.when):
                self.pos[leg.target], self.when[robot] = leg.place, leg.when

    def _fetch(self, j: int, h: int, now: float) -> None:
        gap = np.hypot(*(self.pos[h] - self.pos[j]))
        self.status[j], self.goal[j], self.when[j] = FETCHING, h, now + gap / self.speed[j]
        self.status[h] = HELD

    def left(self) -> np.ndarray:
        """``(m,)`` robots each task still needs beyond those going there (0: done)."""
        going = self.goal[self.status == GOING]
        need = self.needs - np.bincount(going, minlength=self.needs.size)
        return np.where(self.done, 0, need)

    def decide(self, now: float, pending: int = -1) -> None:
        """Every free robot's base policy at ``now``: the convention, else a fetch
        (``pending``: a robot counted free in the others' conventions that does not
        decide and is not fetched: the planning robot, whose choice they do not see)."""
        left = self.left()
        active = left > 0
        free = self.status == FREE
        gaps = np.hypot(*(self.pos[:, None, :] - self.tasks[None]).transpose(2, 0, 1))
        arrive = now + gaps / self.speed[:, None]
        times = np.where(free[:, None] & active[None], arrive, np.inf)
        chosen, memo = {}, {}
        for j in np.flatnonzero(free & (self.K & active).any(axis=1)):
            enough = (self.V[j] & free[:, None]).sum(axis=0) >= left
            if j == pending or not (enough & active & self.K[j]).any():
                continue  # (no task it knows has enough free knowers: the convention idles it)
            key = self.V[j].tobytes()
            if key not in memo:
                memo[key] = convention(times, self.V[j], np.maximum(left, 1))
            if memo[key][j] >= 0:
                chosen[j] = int(memo[key][j])
        for j, t in chosen.items():
            self.status[j], self.goal[j], self.when[j] = GOING, t, arrive[j, t]
        active = self.left() > 0
        for j in np.flatnonzero(self.status == FREE):
            if self.status[j] == FREE and j != pending and (self.K[j] & active).any():
                self._recruit(j, active, pending, now)

    def _recruit(self, j: int, active: np.ndarray, pending: int, now: float) -> None:
        """Free robot ``j``, knowing of tasks that still need robots and not sent to one:
        for each such task (in order) the free knower and unaware free robot nearest each
        other, as ``j`` sees it, are the fetcher and the fetched; ``j`` fetches if it is
        that fetcher, else goes to the nearest such task to wait (one fetcher a task; it
        also waits when nobody is left to fetch while a teammate is being fetched)."""
        free = self.status == FREE
        targets = free.copy()
        targets[pending if pending >= 0 else j] = False
        gaps = np.hypot(*(self.pos[:, None, :] - self.pos[None]).transpose(2, 0, 1))
        gaps = gaps / self.speed[:, None]
        waits = []
        for t in np.flatnonzero(self.K[j] & active):
            fetchers = np.flatnonzero(self.V[j][:, t] & free)
            unaware = np.flatnonzero(~self.V[j][:, t] & targets)
            if unaware.size == 0:  # wait there while a teammate is being fetched
                waits += [t] if (self.status == HELD).any() else []
                continue
            pair = np.argmin(gaps[np.ix_(fetchers, unaware)])
            fetcher, helper = fetchers[pair // unaware.size], unaware[pair % unaware.size]
            if fetcher == j:
                self._fetch(j, int(helper), now)
                return
            waits.append(t)
        if waits:
            t = waits[int(np.argmin(np.hypot(*(self.tasks[waits] - self.pos[j]).T)))]
            gap = np.hypot(*(self.tasks[t] - self.pos[j]))
            self.status[j], self.goal[j], self.when[j] = GOING, t, now + gap / self.speed[j]

    def advance(self, horizon: float) -> float:
        """Play the earliest event (a task done or a meeting); its time (inf: none left
        before ``horizon``)."""
        finish = np.full(self.needs.size, np.inf)
        going = self.status == GOING
        for t in np.flatnonzero(~self.done & (self.left() <= 0)):
            finish[t] = np.sort(self.when[going & (self.goal == t)])[self.needs[t] - 1]
        fetching = np.where(self.status == FETCHING, self.when, np.inf)
        t, j = int(np.argmin(finish)), int(np.argmin(fetching))
        now = min(finish[t], fetching[j])
        if not now <= horizon:
            return np.inf
        if finish[t] <= fetching[j]:
            self.done[t], self.done_at[t] = True, now
            there = going & (self.goal == t)
            self.status[there], self.pos[there] = FREE, self.tasks[t]
            return now
        h = int(self.goal[j])
        self.pos[j] = self.pos[h]
        self.status[[j, h]] = FREE
        self.K[h] |= self.K[j]
        if self.shared:
            self.V[:, h] |= self.K[j]
        else:
            self.V[j, h] |= self.K[j]
            self.V[h, j] |= self.K[j]
            self.V[h, h] = self.K[h]
        return now


def rollout_total(robot: int, leg: Leg, positions, geometry: Geometry, needs,
                  horizon: float, K, V, shared: bool) -> float:  # fmt: skip
    """The sum of the completion times of the tasks anyone knows of (``K``), robot
    ``robot`` taking ``leg`` first and then every robot the base policy, from robots at
    ``positions`` (``(n, 2)``); a task not done by the ``horizon`` costs ``horizon``.

    Examples
    --------
    Two robots 3 and 4 metres from a task needing both, each knowing all know of it:

    >>> g = Geometry(None, [[0.0, 0.0]], [1.0, 1.0])
    >>> K = np.ones((2, 1), dtype=bool)
    >>> V = np.ones((2, 2, 1), dtype=bool)
    >>> rollout_total(0, Leg("task", 0), [[3.0, 0.0], [0.0, 4.0]], g, np.array([2]),
    ...               100.0, K, V, True)
    4.0
    """
    team = _Team(positions, geometry, np.asarray(needs, dtype=int), K, V, shared)
    known = ~team.done
    team.decide(0.0, pending=robot)  # the teammates do not see the robot's choice
    team.start(robot, leg)
    for _ in range(4 * K.size + 4 * K.shape[0] + 8):  # every event changes a set or a task
        now = team.advance(horizon)
        if team.done.all() or not np.isfinite(now):
            break
        team.decide(now)
    cost = np.where(team.done, np.minimum(team.done_at, horizon), horizon)
    return float(cost[known].sum())


def rollout_values(robot: int, geometry: Geometry, sets: Mapping, needs, horizon: float,
                   order: int, helpers: Sequence[int] = (), mixed: bool = False,
                   ) -> tuple[np.ndarray, ...]:  # fmt: skip
    """``(go, fetch)``: the rollout value of going to each task (``(m,)``) and of fetching
    each teammate in ``helpers``, in time units against taking no part (negative: time
    saved); ``inf`` for a task the robot does not know is open.

    Parameters
    ----------
    robot : int
        The planning robot.
    geometry : Geometry
        Positions (or particles of them), tasks and speeds.
    sets : mapping
        Chain -> open tasks known, as :func:`team_views` reads them.
    needs : array_like
        ``(m,)`` robots each task needs.
    horizon : float
        When the rollout stops: a task not done by then costs ``horizon``.
    order : int
        Order of reasoning (:func:`team_views`; fetches are seen by all below 3).
    helpers : sequence of int or Leg
        Teammates it may fetch, or its fetches as :class:`Leg` (a fetched teammate learns
        every task it knows of).
    mixed : bool
        Average over the rollouts at orders 2 .. ``order`` (at order 3: teammates' views
        of each other as the robot's own, and as the chains ``(i, j, l)`` have them).

    Examples
    --------
    >>> g = Geometry([[3.0, 0.0], [0.0, 4.0]], [[0.0, 0.0]], [1.0, 1.0])
    >>> go, _ = rollout_values(0, g, {(0,): [True], (0, 1): [True]}, [2], 100.0, 2)
    >>> go.tolist()                         # done at step 4 rather than never
    [-96.0]
    """
    positions = np.asarray(geometry.positions, dtype=float)
    particles = positions.reshape(-1, *positions.shape[-2:])
    n, m = particles.shape[1], len(needs)
    if particles.shape[2] != 2 or np.asarray(geometry.tasks).shape != (m, 2):
        raise InvalidArgumentError("positions must be (n, 2) or (p, n, 2), tasks (m, 2)")
    needs, horizon = np.asarray(needs, dtype=int), positive(horizon, "horizon")
    own = np.asarray(sets[(robot,)], dtype=bool)
    legs = [Leg("task", t) for t in range(m) if own[t]]
    legs += [h if isinstance(h, Leg) else Leg("fetch", int(h)) for h in helpers]
    levels = range(min(order, 2), order + 1) if mixed else (order,)
    totals = np.zeros(len(legs) + 1)
    for level in levels:
        K, V = team_views(robot, n, sets, level)
        for where in particles:
            for k, leg in enumerate([*legs, Leg("absent")]):
                totals[k] += rollout_total(
                    robot, leg, where, geometry, needs, horizon, K, V, level < 3
                )
    totals /= particles.shape[0] * len(levels)
    go = np.full(m, np.inf)
    go[own] = totals[: int(own.sum())] - totals[-1]
    return go, totals[int(own.sum()) : -1] - totals[-1]
