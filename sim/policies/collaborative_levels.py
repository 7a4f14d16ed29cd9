"""The levels of a collaborative mission: who goes to which task, who explores, who fetches
a teammate (:mod:`epistemica.sim.kinds.collaborative`).

Every level sweeps the workspace in lanes (a boustrophedon, each robot starting at a lane
of its own, a convention every robot knows) while it has nothing better to do, and waits at
a task it goes to; after ``patience`` steps of waiting in vain it explores again for
``hold`` steps before it may come back. They differ in what a robot does with what it
knows. These are the rules' levels, named ``rules-*`` since the planning controller took
the names ``first``, ``second`` and ``third``
(:mod:`~epistemica.sim.policies.collaborative_planning`):

=================  ======================================================================
``convention``     the nearest task it knows of, not known done
``rules-first``    its own knowledge: the known task it expects done soonest (nearest,
                   less ``join_bonus`` m per teammate it sees waiting there)
``rules-shared``   takes every teammate to know what it knows: per task (first the one
                   whose ``needs`` nearest robots assemble soonest: ``soonest``) the
                   ``needs`` robots nearest it go; a robot not among them explores
``rules``          the same over the teammates it knows know the task (the chain
                   ``(i, j)`` is aware of it: they saw the same found, waiting, heading or
                   done event); when those are too few, a knower fetches the nearest
                   teammate that does not know (an intercept: it goes where it predicts
                   that teammate on its sweep, and once near enough heads for the task,
                   so the teammate observes the heading event), or waits at the task
                   when that teammate is predicted in sight of it (a knower that waits
                   while it knows another is out for helpers waits ``backed_patience``
                   steps, and goes with it when nobody else is near to see it wait:
                   ``fetch_together``, ``watch_range``); a knower with nobody to fetch
                   joins the teammates it expects busy at another task (``join_busy``)
                   or, with none, looks for helpers ``seek_limit`` steps, then waits.
                   Teammates out of sight are predicted by :class:`TeammateModel`
                   (``rules-shared`` too).
                   Tasks enough robots it knows know of come first (``complete_first``);
                   news of one more knower renews a waiting robot's patience
                   (``rejoin``); a task as many teammates as it needs have long been
                   known to know of is presumed done (``stale_after``) until, with every
                   task known and nothing to do, it goes to see (``verify``)
``oracle``         ``rules`` with full communication: every robot observes every event
                   and knows where every robot is
``oracle-events``  ``rules`` where every robot observes every event (news of a task
                   spreads at once) but sees teammates only within range: what the
                   oracle owes to news alone
``recruit``        a baseline: ``rules-first``'s choice of task, and, while it sees fewer
                   teammates there than the task needs, it fetches the teammate seen in
                   the last ``fetch_memory`` steps nearest the task (as ``rules`` fetches:
                   the intercept, ``wait_horizon``, ``intercept_limit``) without knowing
                   whether that teammate knows of the task: first-order knowledge plus
                   the recruiting behaviour
``convention+rules``  a baseline: every rule of ``rules`` (the assignment, ``soonest``,
                   fetching, waiting, ``join_busy``, ``seek``, ...) on first-order
                   knowledge: a robot knows which tasks it knows of, never that a teammate
                   knows of one, so it fetches teammates whether or not they know
=================  ======================================================================

Examples
--------
>>> p = CollaborativePolicy("oracle", CollaborativeParameters())
>>> p.style, p.shares
('third', 'everything')
"""

from __future__ import annotations

import numpy as np

from epistemica.sim.engine.joint import JointView as View
from epistemica.sim.policies.collaborative_assignment import (
    EXPLORING,
    FETCHING,
    WAIT,
    CoalitionRules,
)
from epistemica.sim.policies.collaborative_parameters import CollaborativeParameters
from epistemica.sim.policies.collaborative_sweep import meeting_point
from epistemica.sim.policies.collaborative_teammates import TeammateModel
from epistemica.sim.policies.policy import Decisions, Policy

__all__ = [
    "COLLABORATIVE_LEVELS",
    "CollaborativeParameters",
    "CollaborativePolicy",
    "first_order",
    "toward",
]

#: Level name -> (style, what every robot learns at once: "" nothing, "events" every
#: event and task sighting, "everything" those and every robot's place).
COLLABORATIVE_LEVELS = {
    "convention": ("convention", ""),
    "rules-first": ("first", ""),
    "rules-shared": ("shared", ""),
    "rules": ("third", ""),
    "oracle": ("third", "everything"),
    "oracle-events": ("third", "events"),
    "recruit": ("recruit", ""),
    "convention+rules": ("rules", ""),
}


class CollaborativePolicy(CoalitionRules, Policy):
    """One level of :data:`COLLABORATIVE_LEVELS` (each robot decides from its own rows of
    the joint run's view, :class:`~epistemica.sim.engine.joint.JointView`)."""

    def __init__(self, name: str, parameters: CollaborativeParameters) -> None:
        self.name = name
        self.style, self.shares = COLLABORATIVE_LEVELS[name]
        self.parameters = parameters

    def start(self, scenario, robots=None, generators=None) -> None:
        """Called once per trial (``robots`` default: the whole team, which it drives)."""
        robots = range(scenario.n_robots) if robots is None else robots
        generators = [None] * len(robots) if generators is None else generators
        super().start(scenario, robots, generators)
        s, n, m, p = scenario, scenario.n_robots, scenario.n_tasks, self.parameters
        self.s = s
        self.teammates = TeammateModel(
            s,
            p.lane_factor,
            p.particles,
            p.resume,
            (p.rejoin_gap, p.still_fraction, p.heading_slack),
        )
        self.routes = self.teammates.routes
        self.pointer = np.zeros(n, dtype=int)
        self.waiting_since = np.full(n, -1)
        self.company = np.zeros(n, dtype=int)
        self.hold_until = np.zeros((n, m), dtype=int)
        self.held_knowers = np.zeros((n, m), dtype=int)
        self.knowers = np.zeros(n, dtype=int)
        self.fetching = np.full(n, -1)
        self.fetch_since = np.full(n, -1)
        self.gave_up = np.zeros((n, m, n), dtype=bool)
        self.backed = np.zeros(n, dtype=bool)
        self.seeking_since = np.full((n, m), -1)
        self.open_now = np.zeros((n, m), dtype=bool)  # per robot: tasks open by its knowledge
        # plan_watched 2: when robot i's unbroken sighting of j began, and where j was then
        self.in_sight, self.watch_from = np.zeros((n, n), dtype=bool), np.full((n, n), -1)
        self.watch_at = np.zeros((n, n, 2))
        self.missed_at = np.full((n, n), -1)  # plan_missed: when i last missed j in sight

    # -- what a robot predicts ------------------------------------------------------------

    def arc(self, view: View, i: int, j: int) -> float:
        """Arc length of teammate ``j``'s sweep where robot ``i`` expects it now."""
        return self.teammates.arc(view.step, i, j, view.estimates[i, j], int(view.last_seen[i, j]))

    def predicted(self, view: View, i: int, j: int, ahead: int = 0) -> np.ndarray:
        """Where robot ``i`` expects robot ``j`` ``ahead`` steps from now."""
        if i == j:
            return view.poses[i, :2]
        seen = int(view.last_seen[i, j])
        if seen == view.step and ahead == 0:
            return view.estimates[i, j]
        return self.teammates.place(view.step + ahead, i, j, view.estimates[i, j], seen)

    def on_sweep(self, view: View, i: int, j: int, open_tasks: np.ndarray) -> bool:
        """Whether robot ``i`` knows teammate ``j`` is still on its sweep: ``i`` knows of no
        open task (``open_tasks``, by ``i``'s knowledge) that it knows ``j`` knows of, and
        ``j``'s predicted sweep since ``i`` last saw it passed in sight of none of them
        (else ``j`` found one). A task ``i`` does not know of may still have drawn ``j``
        away: ``sweep_memory`` bounds how long ``i`` trusts this."""
        if (view.aware[i, j] & open_tasks).any():
            return False
        seen = view.last_seen[i, j]
        off = self.parameters.off_sweep * self.s.sensing_range
        if seen >= 0 and self.routes[j].gap(view.estimates[i, j]) > off:
            return False  # last seen off its sweep (at a task): where it resumed is unknown
        tasks = self.s.tasks[open_tasks]
        if tasks.size == 0:
            return True
        speed, now = self.s.max_speed[j], self.arc(view, i, j)
        since = max(view.step - max(view.last_seen[i, j], 0), 0)
        start = max(now - since * speed, 0.0)  # now < 0: still on its way to its sweep
        path = self.routes[j].along(np.arange(start, max(now, start) + 1e-9, 2.0))
        gap = np.hypot(*(path[:, None, :] - tasks[None]).transpose(2, 0, 1))
        return bool(gap.min() > self.s.sensing_range)

    def meet(self, view: View, i: int, j: int) -> tuple[int, np.ndarray] | None:
        """Where robot ``i`` meets teammate ``j`` on ``j``'s predicted sweep
        (:func:`~epistemica.sim.policies.collaborative_sweep.meeting_point`)."""
        return meeting_point(
            view.poses[i, :2],
            float(self.s.max_speed[i]),
            self.routes[j],
            self.arc(view, i, j),
            float(self.s.max_speed[j]),
            self.parameters.sight_fraction * self.s.sensing_range,
            self.parameters.intercept_limit,
        )

    def presumed_done(self, view: View, i: int, watched: int = 0) -> np.ndarray:
        """``(m,)`` the tasks robot ``i`` presumes done (``stale_after``): at least as many
        teammates as a task needs have been known to know of it that long, and ``i`` has
        not seen it open for as long. With ``watched`` (``plan_watched``) a knower counts
        from its :meth:`earliest` arrival at the task, if later; at 2 only if it cannot
        have been there before ``i`` saw it away: it was seen sooner after ``i`` knew it
        knew than its walk from the task."""
        old = view.step - self.parameters.stale_after
        since = view.since[i]
        if watched:
            earliest = self.earliest(view, i)
            if watched == 2:  # time to do it before the sighting began, and walk away
                began = self.watch_from[i].astype(float)[:, None]
                first = began - self.walks(self.watch_at[i])
                earliest[(earliest >= 0) & (began >= 0) & (first >= since)] = -1.0
            since = np.maximum(since, earliest)
        knew = (view.since[i] >= 0) & (since <= old)
        knew[i] = False
        return (knew.sum(axis=0) >= np.asarray(self.s.needs)) & (view.open_seen[i] < old)

    def earliest(self, view: View, i: int) -> np.ndarray:
        """``(n, m)`` the earliest step each teammate can have been at each task, as robot
        ``i`` last saw it (-1: never seen, or seen at the task): the step it was seen plus
        its walk from there to within the completion radius of the task.

        Examples
        --------
        Robot 0 (speed 1) seen at step 7 at task 0, 12 m walk from task 1's radius; robot
        1 (speed 2) seen at step 10, 2 m walk from task 0's radius and 9 m from task 1's:

        >>> from types import SimpleNamespace
        >>> policy = CollaborativePolicy("rules", CollaborativeParameters())
        >>> policy.s = SimpleNamespace(tasks=np.array([[0.0, 0.0], [13.0, 0.0]]),
        ...     completion_radius=1.0, max_speed=np.array([1.0, 2.0]), dt=1.0)
        >>> view = SimpleNamespace(last_seen=np.array([[7, 10]]),
        ...                        estimates=np.array([[[0.0, 0.0], [3.0, 0.0]]]))
        >>> policy.earliest(view, 0).tolist()
        [[-1.0, 19.0], [11.0, 14.5]]
        """
        s, seen = self.s, view.last_seen[i].astype(float)
        gap = np.hypot(*(view.estimates[i][:, None, :] - s.tasks[None]).transpose(2, 0, 1))
        away = (seen[:, None] >= 0) & (gap > 2 * s.completion_radius)
        return np.where(away, seen[:, None] + self.walks(view.estimates[i]), -1.0)

    def walks(self, places: np.ndarray) -> np.ndarray:
        """``(n, m)`` steps each robot needs from ``places`` (``(n, 2)``) to within the
        completion radius of each task."""
        s = self.s
        gap = np.hypot(*(places[:, None, :] - s.tasks[None]).transpose(2, 0, 1))
        speed = (np.asarray(s.max_speed) * s.dt)[:, None]
        return np.maximum(gap - s.completion_radius, 0.0) / speed

    def watch(self, view: View) -> None:
        """Note, per robot and teammate, the step its present (or last) unbroken sighting
        of the teammate began and where the teammate was then (``plan_watched`` 2)."""
        now = view.last_seen == view.step
        began = now & ~self.in_sight
        self.watch_from[began], self.watch_at[began] = view.step, view.estimates[began]
        self.in_sight = now

    # -- decisions --------------------------------------------------------------------------

    def decide(self, observations: View, robots: np.ndarray) -> Decisions:
        """The controls of ``robots`` towards their targets (:meth:`plan`), and the task
        each heads to (``Decisions.steer_to``)."""
        targets, steer_to = self.plan(observations)
        s, n = self.s, self.s.n_robots
        controls = toward(observations.poses, targets, s.max_speed, s.max_turn, s.dt)[robots]
        return Decisions(
            controls,
            np.full((len(robots), n), -1),
            np.full(len(robots), np.nan),
            np.zeros(len(robots), dtype=int),
            steer_to=steer_to[robots],
        )

    def plan(self, view: View) -> tuple[np.ndarray, np.ndarray]:
        """``(targets (n, 2), steer_to (n,))``: where each robot goes and the task it
        heads to (-1 exploring, -2 fetching a teammate)."""
        n, k = self.s.n_robots, view.knowledge
        if self.style == "rules":  # convention+rules: what teammates know is not known
            view = first_order(view)
        if self.style != "convention" and self.style != "first":  # they predict teammates
            self.teammates.observe(view.step, view.poses, view.estimates, view.last_seen)
        targets, steer_to = np.zeros((n, 2)), np.full(n, EXPLORING)
        aware = view.aware if self.style in ("third", "rules") else None
        self.open_now = np.zeros((n, self.s.n_tasks), dtype=bool)
        for i in range(n):
            done = k.knows_done((i,))
            presumed = np.zeros_like(done)
            if aware is not None and self.parameters.stale_after:
                presumed = self.presumed_done(view, i) & ~done
                done = done | presumed
            known = view.aware[i, i] & ~done
            self.open_now[i] = known
            waiting = self._waiting(view, i)
            available = known & self.unheld(view, i, waiting, aware)
            choice = self._choose(view, i, available, aware, waiting)
            if choice == ("explore",) and self.parameters.verify:
                choice = self._verify(view, i, presumed)
            targets[i], steer_to[i] = self._act(view, i, choice, waiting)
        return targets, steer_to

    def unheld(self, view: View, i: int, waiting: np.ndarray, aware) -> np.ndarray:
        """``(m,)`` the tasks robot ``i`` may go to as far as its patience goes: not on
        hold (it waited there ``patience`` steps in vain less than ``hold`` steps ago), or
        its coming would complete them (``waiting``: teammates it sees standing there), or
        it learnt of a new knower since (``rejoin``, with the ledger ``aware``)."""
        full = waiting >= np.asarray(self.s.needs) - 1  # it would complete them: go
        if aware is not None and self.parameters.rejoin:  # a new knower: try again
            full |= aware[i].sum(axis=0) > self.held_knowers[i]
        return (self.hold_until[i] <= view.step) | full

    def _verify(self, view: View, i: int, presumed: np.ndarray) -> tuple:
        """What robot ``i``, with nothing to do, does about the tasks it presumes done
        (``presumed``): it goes to see the nearest once it knows of every task of the
        mission (nothing is left to find), and explores otherwise."""
        if not (presumed.any() and view.aware[i, i].all()):
            return ("explore",)
        return ("task", self._nearest(view, i, np.flatnonzero(presumed)))

    def standing(self, view: View, i: int) -> np.ndarray:
        """``(n, m)`` which robots robot ``i`` sees now standing at each task (within two
        completion radii of it, where it estimates them)."""
        sees = view.last_seen[i] == view.step
        gap = np.hypot(*(view.estimates[i][:, None, :] - self.s.tasks[None]).transpose(2, 0, 1))
        return sees[:, None] & (gap <= 2 * self.s.completion_radius)

    def _waiting(self, view: View, i: int) -> np.ndarray:
        """``(m,)`` teammates robot ``i`` sees standing at each task now."""
        at = self.standing(view, i)
        at[i] = False
        return at.sum(axis=0)

    def _choose(self, view: View, i: int, available: np.ndarray, aware, waiting) -> tuple:
        """``("task", t)``, ``("fetch", t, j)``, or ``("explore",)``."""
        tasks = np.flatnonzero(available)
        self.backed[i] = False
        if tasks.size == 0:
            return ("explore",)
        here = view.poses[i, :2]
        gaps = np.hypot(*(self.s.tasks[tasks] - here).T)
        if self.style == "convention":
            return ("task", int(tasks[np.argmin(gaps)]))
        if self.style in ("first", "recruit"):
            score = gaps - self.parameters.join_bonus * waiting[tasks]
            t = int(tasks[np.argmin(score)])
            return self._fetch_for(view, i, t) if self.style == "recruit" else ("task", t)
        return self._assign(view, i, tasks, aware)

    def _fetch_for(self, view: View, i: int, t: int) -> tuple:
        """``recruit``: robot ``i`` fetches a teammate for task ``t`` while it sees too few
        standing there, any teammate seen lately but those (it does not know who knows)."""
        s = self.s
        sees = view.last_seen[i] == view.step
        at_t = sees & (np.hypot(*(view.estimates[i] - s.tasks[t]).T) <= 2 * s.completion_radius)
        at_t[i] = True
        if at_t.sum() >= s.needs[t]:
            return ("task", t)
        where = np.array([self.predicted(view, i, j) for j in range(s.n_robots)])
        fetch = self._recruit(view, i, t, at_t, where)
        return ("task", t) if fetch is None or fetch == WAIT else ("fetch", t, fetch)

    def _act(self, view: View, i: int, choice: tuple, waiting) -> tuple[np.ndarray, int]:
        s, p, step = self.s, self.parameters, view.step
        here = view.poses[i, :2]
        if choice[0] != "fetch":
            self.fetching[i], self.fetch_since[i] = -1, -1
        if choice[0] == "task":
            t = choice[1]
            if np.hypot(*(here - s.tasks[t])) <= s.completion_radius:
                knowers = int(view.aware[i, :, t].sum())
                news = p.rejoin and knowers > self.knowers[i]  # one more knows: it may come
                if self.waiting_since[i] < 0 or waiting[t] > self.company[i] or news:
                    self.waiting_since[i] = step  # a teammate joined: patience anew
                self.company[i], self.knowers[i] = waiting[t], knowers
                patience = p.backed_patience if self.backed[i] else p.patience
                if step - self.waiting_since[i] >= patience:
                    self.hold_until[i, t] = step + p.hold
                    self.held_knowers[i, t] = knowers
                    self.waiting_since[i] = -1
                    self.seeking_since[i, t] = -1  # after the hold it looks for helpers anew
            else:
                self.waiting_since[i] = -1
            return s.tasks[t], t
        self.waiting_since[i] = -1
        if choice[0] == "fetch":
            t, j = choice[1], choice[2]
            if self.fetching[i] != j:
                self.fetching[i], self.fetch_since[i] = j, step
            now = self.predicted(view, i, j)
            if view.last_seen[i, j] == step and np.hypot(*(now - here)) <= self._hail(i, j):
                return s.tasks[t], t  # it sees i head for the task, even as both move apart
            if step - self.fetch_since[i] >= p.intercept_limit:
                self.gave_up[i, t, j] = True
            if p.meet_ahead:
                if np.hypot(*(now - here)) <= p.lost_range * s.sensing_range:
                    self.gave_up[i, t, j] = True  # not where its sweep puts it: it left it
                met = self.meet(view, i, j)
                if met is not None:
                    return met[1], FETCHING
            return now, FETCHING
        route = self.routes[i]
        while np.hypot(*(route.points[self.pointer[i]] - here)) < self.parameters.waypoint_reach:
            self.pointer[i] = (self.pointer[i] + 1) % len(route.points)
        return route.points[self.pointer[i]], EXPLORING


def toward(poses: np.ndarray, targets: np.ndarray, max_speed, max_turn, dt: float) -> np.ndarray:
    """Controls ``(n, 2)`` that turn each robot towards its target (within ``max_turn``)
    and move it at most ``max_speed``, never past the target.

    As :func:`~epistemica.sim.policies.policy.steer`, with the heading change wrapped to
    ``[-pi, pi)`` rather than ``(-pi, pi]``: the collaborative levels were tuned, and
    their trials recorded, with this one.

    Examples
    --------
    >>> toward(np.array([[0.0, 0.0, 0.0]]), np.array([[0.0, 0.5]]), 1.0, np.pi, 1.0).round(4)
    array([[0.5   , 1.5708]])
    """
    delta = targets - poses[:, :2]
    distance = np.hypot(delta[:, 0], delta[:, 1])
    change = np.arctan2(delta[:, 1], delta[:, 0]) - poses[:, 2]
    change = (change + np.pi) % (2 * np.pi) - np.pi
    change = np.where(distance > 0, np.clip(change, -max_turn, max_turn), 0.0)
    speed = np.minimum(max_speed, distance / dt)
    return np.column_stack([speed, change])


def first_order(view: View) -> View:
    """``view`` with only first-order knowledge of tasks: robot ``i`` knows which tasks it
    knows of (``aware[i, i]``), and of no teammate that it knows of one.

    Examples
    --------
    >>> aware = np.ones((2, 2, 1), dtype=bool)
    >>> v = View(0, None, None, None, None, aware, np.zeros((2, 2, 1), dtype=int), None)
    >>> first_order(v).aware[:, :, 0].tolist(), int(first_order(v).since[0, 1, 0])
    ([[True, False], [False, True]], -1)
    """
    own = np.eye(view.aware.shape[0], dtype=bool)[:, :, None] & view.aware
    return view._replace(aware=own, since=np.where(own, view.since, -1))
