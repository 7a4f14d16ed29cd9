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
from epistemica.aif.task_completion import Credit, completion_times
from epistemica.aif.task_context import Fetch, TaskContext, convention, softmax
from epistemica.aif.task_rollout import Geometry, Leg, rollout_values
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["Fetch", "Geometry", "TaskPlan", "TaskPlanner", "completion_times", "convention"]


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
    fetchers : bool
        Teammates' predicted choices include their fetches (given ``meetings`` to
        :meth:`plan`): a teammate ``l`` that knows of a task a robot ``h`` does not (as the
        chain ``(i, l, h)`` has it) may fetch ``h``, valued like its other options, and a
        fetch predicted with probability ``q`` adds two arrivals at the task, ``l`` and
        ``h`` at the meeting's time, each coming with ``q`` (independently, an
        approximation): the completion model then sees recruited coalitions form.
    rollout : float
        The horizon of a rollout over chains of fetches, in the units of the arrivals (0:
        none): going to a task and fetching are valued by
        :func:`~epistemica.aif.task_rollout.rollout_values` when :meth:`plan` is given
        ``geometry`` (a fetch's value times the probability its helper is found; at order
        3 the rollouts of orders 2 and 3 averaged).
    knowers : bool
        Coming to a task earns ``credit`` only when at least ``needs`` robots know of it
        (as the chain's sets have it, the robot included): where fewer do, nobody else
        can come, and a robot waiting there alone saves nothing until it brings one (a
        fetch still earns credit; its baseline, without the fetch, then earns none).
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
        fetchers: bool = False,
        rollout: float = 0.0,
        knowers: bool = False,
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
        self.fetchers = bool(fetchers)
        self.rollout = float(as_finite(rollout, "rollout"))
        self.knowers = bool(knowers)
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
        meetings=None,
        geometry: Geometry | None = None,
        waiting: Mapping[int, int] | None = None,
        stands: Mapping[int, int] | None = None,
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
        meetings : array_like, optional
            ``(n, n, m)``: when ``l`` and ``h`` reach task ``t`` if ``l`` fetches ``h``.
        geometry : Geometry, optional
            Where robots and tasks are, for ``rollout`` (without it: one-step values).
        waiting, stands : mapping, optional
            Teammate -> the task it is seen waiting at: ``waiting`` predicts it there (it has
            chosen); a fetch of a ``stands`` one elsewhere is charged what that task loses.

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
        a, robot = self._checked(arrivals, robot, sets)
        n, m = a.shape[0], self.needs.shape[0]
        waits = [self._waiters(w, robot, n) for w in (waiting, stands)]
        context = TaskContext(self, a, sets, unknown or {}, self._meetings(meetings, n), *waits)
        own = context.costs((robot,), self.order)
        fetching = self.order >= 1 and n > 1
        if self.rollout > 0 and geometry is not None and fetching:
            own, extra = self._rollout(robot, geometry, sets, fetches, own)
        else:
            extra = (
                context.fetch_costs(robot, fetches) if fetching else np.full(len(fetches), np.inf)
            )
        G = self._biased(np.concatenate([own, extra]), context, robot, previous)
        best = int(np.argmin(G))
        if G[m] <= G[best] + 1e-9 * self.tau:  # nothing saves more: explore (ties too)
            best = m
        below = max(self.order - 1, 0)
        mine = softmax(own, self.tau)
        preds = np.stack(
            [mine if j == robot else context.choice((robot, j), below) for j in range(n)]
        )
        if best < m:
            kind, task, helper = "task", best, -1
        elif best == m:
            kind, task, helper = "explore", -1, -1
        else:
            fetch = fetches[best - m - 1]
            kind, task, helper = "fetch", int(fetch.task), int(fetch.helper)
        return TaskPlan(kind, task, helper, best, G / self.tau, preds)

    def _biased(self, G: np.ndarray, context: TaskContext, robot: int, previous) -> np.ndarray:
        """``G`` with the convention's prior and the commitment to ``previous``."""
        m = self.needs.shape[0]
        if self.convention > 0 and self.order >= 1:  # the shared convention breaks standoffs
            prior = np.full(G.size, 0.05 / G.size)
            prior[: m + 1] += 0.95 * softmax(context.costs((robot,), 0), self.tau)
            if self.recruit:  # a fetch is as likely as exploring (the convention's free time)
                prior[m + 1 :] = prior[m]
            G = G - self.convention * self.tau * np.log(prior)
        if previous is not None and 0 <= previous < G.size and np.isfinite(G[previous]):
            G = G + self.commitment * self.tau
            G[previous] -= self.commitment * self.tau
        return G

    def _checked(self, arrivals, robot: int, sets) -> tuple[np.ndarray, int]:
        """The arrivals as an ``(n, m)`` array and the robot, checked."""
        a = np.asarray(arrivals, dtype=float)
        n, m = a.shape[0], self.needs.shape[0]
        robot = check_robot(robot, n)
        if a.shape != (n, m) or np.isnan(a).any():
            raise InvalidArgumentError(f"arrivals must be ({n}, {m}) numbers, got {a.shape}")
        if (robot,) not in sets:
            raise InvalidArgumentError("sets needs the robot's own chain", hint="(robot,)")
        return a, robot

    def _rollout(self, robot: int, geometry: Geometry, sets, fetches, own):
        """``own`` (tasks, explore) and the fetches' values, by rollout where a task is
        an option (a fetch's value times the probability its helper is found)."""
        legs = list(dict.fromkeys(Leg("fetch", int(f.helper), f.meeting, f.place) for f in fetches))
        go, fetched = rollout_values(
            robot, geometry, sets, self.needs, self.rollout, self.order, legs, True
        )
        m = self.needs.shape[0]
        own = own.copy()
        own[:m] = np.where(np.isfinite(own[:m]), go, np.inf)
        value = dict(zip(legs, fetched, strict=True))
        return own, np.array([f.found * value[Leg("fetch", int(f.helper), f.meeting, f.place)]
                              for f in fetches])  # fmt: skip

    def _waiters(self, waiting, robot: int, n: int) -> dict:
        """The checked ``waiting``: teammates (not ``robot``) -> tasks."""
        out = {int(j): int(t) for j, t in (waiting or {}).items()}
        m = self.needs.shape[0]
        if any(not (0 <= j < n and j != robot and 0 <= t < m) for j, t in out.items()):
            raise InvalidArgumentError(f"waiting and stands map teammates to tasks: {waiting}")
        return out

    def _meetings(self, meetings, n: int) -> np.ndarray | None:
        """The checked ``(n, n, m)`` meeting times, or None without ``fetchers``."""
        if not self.fetchers or meetings is None:
            return None
        meet = np.asarray(meetings, dtype=float)
        m = self.needs.shape[0]
        if meet.shape != (n, n, m) or np.isnan(meet).any():
            raise InvalidArgumentError(f"meetings must be ({n}, {n}, {m}), got {meet.shape}")
        return meet
