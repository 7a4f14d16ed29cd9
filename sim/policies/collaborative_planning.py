"""The planning levels of a collaborative mission: options chosen by expected free energy
(:class:`epistemica.aif.task_planning.TaskPlanner`) rather than ordered by rules.

Each step every robot scores its options (go to an open task it knows of, fetch a teammate
it knows does not know of one, explore) by the expected time they save the mission, with
teammates' choices predicted by the same planner one order down over what the robot knows
they know (the task ledger of the DEL state: ``aware[i, j]`` and, at order 3, the chains
``(i, j, l)``). What it then does reuses the rules' primitives of
:class:`~epistemica.sim.policies.collaborative_levels.CollaborativePolicy`: the sweep when
exploring, the intercept (:meth:`~CollaborativePolicy.meet`) when fetching, where a
teammate out of sight is (:class:`~epistemica.sim.policies.collaborative_teammates.TeammateModel`),
which tasks have long been presumed done, and going to see one of those when every task is
known and no option saves anything.

=======================  ================================================================
``first``                order 1 on first-order knowledge: teammates predicted (order 0)
                         over its own tasks; any teammate may be fetched
``second``               order 2 over the nested sets ``(i, j)``
``third``                order 3 over ``(i, j)`` and ``(i, j, l)``
``third-shared``         order 3, every teammate taken to know what it knows (no fetching)
``third-priormode``      the same beliefs, no planning: the convention (order 0)
=======================  ================================================================

Examples
--------
>>> from epistemica.sim import simulate
>>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
>>> s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1)
>>> simulate(s, "third", seed=1).success
True
>>> PlanningCollaborativePolicy("second", CollaborativeParameters()).order
2
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from epistemica.aif.task_planning import Fetch, Geometry, TaskPlanner
from epistemica.sim.engine.joint import JointView as View
from epistemica.sim.policies.collaborative_levels import CollaborativePolicy, first_order
from epistemica.sim.policies.collaborative_parameters import CollaborativeParameters
from epistemica.sim.policies.collaborative_sightings import Sightings

__all__ = [
    "PLANNING_LEVELS",
    "CollaborativeParameters",
    "Decision",
    "PlanningCollaborativePolicy",
    "explain",
]

#: Level name -> (order, how it models teammates' knowledge: "first" its own view only,
#: "nested" the ledger's chains, "shared" everyone knows what it knows).
PLANNING_LEVELS = {
    "first": (1, "first"),
    "second": (2, "nested"),
    "third": (3, "nested"),
    "third-shared": (3, "shared"),
    "third-priormode": (0, "nested"),
}


class Decision(NamedTuple):
    """One robot's plan at one step, as :attr:`PlanningCollaborativePolicy.trace` keeps it.

    Attributes
    ----------
    step, robot : int
        When, and who decided.
    options : tuple
        ``(kind, task, helper)`` of every option, in the order of ``G``.
    G : numpy.ndarray
        Expected free energy of each option (nats; ``inf``: not an option).
    choice : int
        The index of the option chosen.
    arrivals : numpy.ndarray
        ``(n, m)`` steps the robot expects each robot to take to each task.
    predictions : numpy.ndarray
        ``(n, m + 1)`` each robot's predicted choice of a task or exploring.
    particles : numpy.ndarray
        ``(n,)`` the starts of each teammate still possible (its place's particles,
        :class:`TeammateModel`; one seen keeps the count it had when first seen, and the
        robot's own row is the whole grid).
    sets : dict
        Chain -> the open tasks the robot knows the chain's last robot knows of.
    """

    step: int
    robot: int
    options: tuple
    G: np.ndarray
    choice: int
    arrivals: np.ndarray
    predictions: np.ndarray
    particles: np.ndarray
    sets: dict


def explain(decision: Decision) -> str:
    """A decision as a Markdown table, best option first (options that are none left out).

    Examples
    --------
    >>> d = Decision(7, 0, (("task", 0, -1), ("explore", -1, -1)), np.array([-0.5, 0.0]),
    ...              0, np.zeros((1, 1)), np.zeros((1, 2)), np.zeros(1), {})
    >>> print(explain(d))
    | option | G (nats) | chosen |
    |---|---:|---|
    | task 0 | -0.500 | yes |
    | explore | 0.000 |  |
    """
    lines = ["| option | G (nats) | chosen |", "|---|---:|---|"]
    for k in np.argsort(decision.G, kind="stable"):
        if np.isfinite(decision.G[k]):
            kind, task, helper = decision.options[k]
            name = {"task": f"task {task}", "explore": "explore"}.get(
                kind, f"fetch {helper} for task {task}"
            )
            mark = "yes" if k == decision.choice else ""
            lines.append(f"| {name} | {decision.G[k]:.3f} | {mark} |")
    return "\n".join(lines)


class PlanningCollaborativePolicy(Sightings, CollaborativePolicy):
    """One level of :data:`PLANNING_LEVELS`.

    Parameters
    ----------
    name : str
        A key of :data:`PLANNING_LEVELS`.
    parameters : CollaborativeParameters
        The mission's constants (the ``plan_*`` fields are the planner's).
    trace : bool
        Keep every decision of the last trial in :attr:`trace` (a list of
        :class:`Decision`; None without).

    Examples
    --------
    >>> from epistemica.sim import simulate
    >>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
    >>> policy = PlanningCollaborativePolicy("third", CollaborativeParameters(), trace=True)
    >>> trial = simulate(CollaborativeScenario.drawn(robots=3, needs=(2,), seed=1), policy, seed=1)
    >>> first = policy.trace[0]
    >>> first.step, first.robot, first.options[first.choice]
    (0, 0, ('fetch', 0, 2))
    """

    def __init__(self, name: str, parameters: CollaborativeParameters, trace: bool = False) -> None:
        self.name = name
        self.order, self.model = PLANNING_LEVELS[name]
        self.style, self.shares = "plan", ""
        self.parameters = parameters
        self.trace: list[Decision] | None = [] if trace else None

    def start(self, scenario, robots=None, generators=None) -> None:
        """Called once per trial: the rules' state, and one planner for the mission."""
        super().start(scenario, robots, generators)
        s, p = scenario, self.parameters
        speed = float(np.mean(s.max_speed))
        crossing = s.workspace / (speed * s.dt)  # steps to cross the workspace
        self.planner = TaskPlanner(
            s.needs,
            order=self.order,
            temperature=p.plan_temperature * crossing,
            fail=p.plan_repair * crossing,
            explore=p.plan_explore,
            commitment=p.plan_commitment,
            convention=p.plan_convention,
            credit=p.plan_credit,
            recruit=p.plan_recruit,
            timed=p.plan_timed,
            quorum=int(p.plan_quorum),
            later=p.plan_later * crossing if p.plan_later > 0 else np.inf,
            rendezvous=bool(p.plan_rendezvous),
            mission=bool(p.plan_mission),
            pool=bool(p.plan_pool),
            fetchers=bool(p.plan_fetchers),
            rollout=p.plan_rollout * crossing,
            knowers=bool(p.plan_knowers),
        )
        # seen[i, j, t]: robot i saw teammate j with task t in sight (j knows of t)
        self.seen = np.zeros((s.n_robots, s.n_robots, s.n_tasks), dtype=bool)
        # ever[i, t]: robot i has presumed t done; doubted[i, t]: and then found it open
        self.ever = np.zeros((s.n_robots, s.n_tasks), dtype=bool)
        self.doubted = np.zeros((s.n_robots, s.n_tasks), dtype=bool)
        # hailing informs: teammates who see a robot head for a task learn of it
        self.hails = any(e.trigger.kind == "heads" and e.reveals for e in s.events)
        # without one, a teammate learns of a task when it sees a robot come within ``reach``
        # of it (the found event: None if none) or stand there (``settle``)
        reach = [e.trigger.value for e in s.events if e.trigger.kind == "within" and e.reveals]
        self.reach = max(reach) if reach else None
        self.settle = any(e.trigger.kind == "settles" and e.reveals for e in s.events)
        # events, none of them a hail (a world without events keeps the hail model: tests)
        self.silent = bool(s.events) and not self.hails
        self.held = np.zeros(s.n_tasks, dtype=bool)  # the deciding robot's tasks on hold
        self.previous = [None] * s.n_robots  # (kind, task, helper) of each robot's last plan
        # hailed[i, t, j]: the step robot i first came within hailing distance of j, in
        # sight, fetching it for t (-1: never)
        self.hailed = np.full((s.n_robots, s.n_tasks, s.n_robots), -1)
        self.back: list = [None] * s.n_robots  # the fetch each robot hailed in, if on it
        self.last_plans: list = [None] * s.n_robots
        self.waiting_now: dict[int, int] = {}  # the deciding robot's waiters (plan_waiters)
        if self.trace is not None:
            self.trace = []  # this trial's decisions

    def plan(self, view: View) -> tuple[np.ndarray, np.ndarray]:
        """``(targets (n, 2), steer_to (n,))``, as the rules' :meth:`CollaborativePolicy.plan`."""
        n, k = self.s.n_robots, view.knowledge
        if self.model == "first":
            view = first_order(view)
        # who stands still, read only by plan_waiters (off by default): not on every step
        self.still = self.standing_still(view) if self.parameters.plan_waiters else None
        self.teammates.observe(view.step, view.poses, view.estimates, view.last_seen)
        if self.parameters.plan_watched == 2:  # the sighting runs it reads
            self.watch(view)
        if self.parameters.plan_retry:  # a teammate seen again is where it is seen
            self.gave_up &= ~(view.last_seen == view.step)[:, None, :]
        self.missed(view)  # plan_missed: not where predicted, in sight: given up
        if self.parameters.plan_sighted and self.model == "nested":
            self.seen |= self.sighted(view)
        targets, steer_to = np.zeros((n, 2)), np.full(n, -1)
        self.open_now = np.zeros((n, self.s.n_tasks), dtype=bool)
        for i in range(n):
            done = k.knows_done((i,))
            presumed = np.zeros_like(done)
            if self.parameters.stale_after:
                presumed = self.presumed_done(view, i, int(self.parameters.plan_watched)) & ~done
            closed = done | presumed
            self.open_now[i] = view.aware[i, i] & ~closed
            self.ever[i] |= presumed
            self.doubted[i] = self.ever[i] & self.open_now[i] & bool(self.parameters.plan_presumed)
            waiting = self._waiting(view, i)
            self.held = np.zeros(self.s.n_tasks, dtype=bool)
            if self.parameters.plan_hold:  # the rules' patience: no task to wait at forever
                self.held = ~self.unheld(view, i, waiting, view.aware)
            choice = self.choose(view, i, closed)
            if choice == ("explore",) and self.parameters.verify:
                choice = self._verify(view, i, presumed)
            self.backed[i] = False
            targets[i], steer_to[i] = self._act(view, i, self._leg(i, choice), waiting)
            if choice[0] == "fetch" and steer_to[i] == choice[1]:  # the hail: it turns back
                if self.hailed[i, choice[1], choice[2]] < 0:
                    self.hailed[i, choice[1], choice[2]] = view.step
                self.back[i] = choice
        return targets, steer_to

    def _leg(self, i: int, choice: tuple) -> tuple:
        """What robot ``i`` does of ``choice``: with ``plan_back``, in a mission with no
        ``heads to`` event, a fetch whose hail it has made goes on to its task (the trip
        back, where the helper may see it find the task or stand at it: :meth:`told`),
        rather than turning for the helper again once out of hailing distance."""
        if choice != self.back[i]:
            self.back[i] = None
            return choice
        return ("task", choice[1]) if self.parameters.plan_back and self.silent else choice

    def knows(self, view: View, i: int) -> np.ndarray:
        """``(n, m)`` the tasks robot ``i`` knows each teammate knows of: the ledger, and
        with ``plan_sighted`` the tasks it saw that teammate have in sight, and with
        ``plan_waiters`` the task each teammate waits at (:meth:`waiters`); with
        ``plan_presumed`` not a task ``i`` presumed done and then found open, where ``i``
        does not see the teammate stand (:meth:`presuming`)."""
        knows = (view.aware[i] | self.seen[i]) & ~self.presuming(view, i)
        for j, task in self.waiting_now.items():
            knows[j, task] = True
        return knows

    def arrivals(self, view: View, i: int) -> np.ndarray:
        """``(n, m)`` steps robot ``i`` expects each robot to take to each task."""
        s = self.s
        self.where = np.array([self.predicted(view, i, j) for j in range(s.n_robots)])
        gaps = np.hypot(*(self.where[:, None, :] - s.tasks[None]).transpose(2, 0, 1))
        return gaps / (np.asarray(s.max_speed, dtype=float).reshape(-1, 1) * s.dt)

    def meetings(self) -> np.ndarray:
        """``(n, n, m)`` steps until robots ``l`` and ``h`` reach each task if ``l`` fetched
        ``h``, as the last :meth:`arrivals` placed them: ``l`` goes to where ``h`` is
        predicted, then both go to the task at the slower one's speed."""
        s = self.s
        speed = np.asarray(s.max_speed, dtype=float) * s.dt
        gap = np.hypot(*(self.where[:, None] - self.where[None]).transpose(2, 0, 1))
        back = np.hypot(*(self.where[:, None, :] - s.tasks[None]).transpose(2, 0, 1))
        slower = np.minimum(speed[:, None], speed[None])
        return (gap / speed[:, None])[..., None] + back[None] / slower[..., None]

    def chains(self, view: View, i: int, closed: np.ndarray) -> tuple[dict, dict]:
        """Robot ``i``'s open tasks and unknown-task counts per chain, as the level models
        its teammates' knowledge (with ``plan_rollout``, a teammate it sees standing at a
        task, within two completion radii, is taken to know of it)."""
        n, m, k = self.s.n_robots, self.s.n_tasks, view.knowledge
        known = {(i,): view.aware[i, i]}
        if self.model == "nested":
            knows = self.knows(view, i)
            known.update({(i, j): knows[j] for j in range(n) if j != i})
        gone = self.presuming(view, i)
        if self.model == "nested" and self.order >= 3:
            for j in range(n):
                for h in range(n):
                    if j != i and h != j:
                        known[(i, j, h)] = k.knows_goals((i, j, h)) & ~gone[h]
        sets = {c: aware & ~closed for c, aware in known.items()}
        unknown = {c: m - int(aware.sum()) for c, aware in known.items()}
        if self.parameters.plan_rollout and self.model == "nested":
            for j, there in enumerate(self.standing(view, i)):
                if j != i:  # a teammate seen standing at a task it knows knows of it
                    sets[(i, j)] = sets[(i, j)] | (there & sets[(i,)])
        return sets, unknown

    def fetches(self, view: View, i: int) -> list[Fetch]:
        """The teammates robot ``i`` may fetch: for each open task it knows of, each
        teammate it does not know knows of it and meets on its sweep (the rules'
        intercept), found with probability ``exp(-age / fetch_memory)``. With
        ``plan_hailed``, not for a task it has hailed that teammate for already (it
        came within hailing distance, in sight, and turned for the task): if the hail had
        told it, the ledger would say so; a second hail tells it no more. With
        ``plan_told``, in a mission with events but no ``heads to`` event, only for the
        tasks :meth:`told` says the fetch shows the teammate. With
        ``plan_spread``, a teammate never seen is found only as often as its possible
        starts put it in sight of the meeting (:meth:`TeammateModel.spread`). With
        ``plan_rollout``, not a teammate it knows has left its sweep for a task
        (:meth:`~CollaborativePolicy.on_sweep` over the tasks it would be fetched for)."""
        s, p = self.s, self.parameters
        if self.model == "shared" or (p.plan_hail and not self.hails):
            return []  # nobody to tell, or no way to tell: a hail shows nothing
        speed = np.asarray(s.max_speed, dtype=float) * s.dt
        out, knows = [], self.knows(view, i)
        for j in range(s.n_robots):
            unaware = self.open_now[i] & ~knows[j] & ~self.gave_up[i, :, j]
            if p.plan_hailed:  # hailed and still not known to know: hailing again tells no more
                unaware &= self.hailed[i, :, j] < 0
            if p.plan_chase and self.silent:  # chased that long since the hail, and untold
                unaware &= ~self.chased(view, i, j)
            if j == i or not unaware.any() or (p.plan_lost and self.lost(view, i, j)):
                continue
            if p.plan_rollout and not self.on_sweep(view, i, j, unaware):
                continue  # seen off its sweep, or it passed a task: the intercept misses it
            met = self.met(view, i, j)
            if met is None:
                continue
            if p.plan_told and self.silent:  # a hail tells nothing: only what j sees after
                unaware = unaware & self.told(view, i, j, met, j in self.waiting_now)
            age = view.step - max(int(view.last_seen[i, j]), 0)
            found = float(np.exp(-age / max(p.fetch_memory, 1)))
            if p.plan_spread and view.last_seen[i, j] < 0:
                found *= self.teammates.spread(view.step + met[0], i, j, met[1])
            for t in np.flatnonzero(unaware):
                back = float(np.hypot(*(met[1] - s.tasks[t])))
                out.append(Fetch(int(t), j, met[0] + back / speed[i], met[0] + back / speed[j],
                                 found, float(met[0]), tuple(map(float, met[1]))))  # fmt: skip
        return out

    def chased(self, view: View, i: int, j: int) -> np.ndarray:
        """``(m,)`` the tasks robot ``i`` first hailed teammate ``j`` for at least
        ``plan_chase`` steps ago (``j`` still not known to know of them): in a mission with
        no ``heads to`` event a hail tells nothing, and a teammate that has not seen the
        fetcher find or wait at the task in that time is most likely out fetching itself
        (mission 165: two fetchers chased each other to the step limit)."""
        first = self.hailed[i, :, j]
        return (first >= 0) & (view.step - first >= self.parameters.plan_chase)

    def lost(self, view: View, i: int, j: int) -> bool:
        """Whether robot ``i`` knows teammate ``j`` is not on its sweep (``plan_lost``):
        it gave up fetching ``j`` for some task (``j`` was not where its sweep put it, and
        that says where ``j`` is, whatever the task), or never saw ``j`` and every start
        that would have kept ``j`` out of its sight is ruled out (``j`` left its sweep).
        Until ``i`` sees ``j`` again (``plan_retry``) an intercept on the sweep is a guess."""
        if self.gave_up[i, :, j].any():
            return True
        return bool(view.last_seen[i, j] < 0 and not self.teammates.alive[i, j].any())

    def met(self, view: View, i: int, j: int) -> tuple[float, np.ndarray] | None:
        """When and where robot ``i`` meets teammate ``j`` it would fetch: on ``j``'s
        predicted sweep (:meth:`~CollaborativePolicy.meet`), or, with ``plan_insight`` and
        ``j`` in sight now, where it is seen, once ``i`` has closed to hailing distance
        (``j`` may be off its sweep, out fetching itself: its sweep says nothing of where
        it goes, and what ``i`` does when fetching is to head for it and hail); with
        ``plan_waiters``, a teammate it sees waiting at a task likewise (:meth:`waiters`)."""
        insight = self.parameters.plan_insight and view.last_seen[i, j] == view.step
        if not (insight or j in self.waiting_now):  # plan_waiters: it waits where it is seen
            return self.meet(view, i, j)
        there = view.estimates[i, j]
        gap = float(np.hypot(*(there - view.poses[i, :2])))
        steps = max(gap - self._hail(i, j), 0.0) / (self.s.max_speed[i] * self.s.dt)
        return steps, there

    def choose(self, view: View, i: int, closed: np.ndarray) -> tuple:
        """Robot ``i``'s option: ``("task", t)``, ``("fetch", t, j)`` or ``("explore",)``."""
        m = self.s.n_tasks
        self.waiting_now = self.waiters(view, i)
        arrivals = self.arrivals(view, i)
        arrivals[i, self.held] = np.inf  # on hold: going there is no option
        sets, unknown = self.chains(view, i, closed)
        fetches = self.fetches(view, i) if self.order >= 1 else []
        keys = [("task", t, -1) for t in range(m)] + [("explore", -1, -1)]
        keys += [("fetch", f.task, f.helper) for f in fetches]
        previous = keys.index(self.previous[i]) if self.previous[i] in keys else None
        p, s = self.parameters, self.s
        meetings = self.meetings() if p.plan_fetchers else None
        speed = np.asarray(s.max_speed, dtype=float) * s.dt
        geometry = Geometry(self.where, s.tasks, speed) if p.plan_rollout else None
        plan = self.planner.plan(
            i,
            arrivals,
            sets,
            unknown,
            fetches,
            previous,
            meetings,
            geometry,
            waiting=self.staying(),
            stands=self.waiting_now,
        )
        self.last_plans[i] = plan
        self.previous[i] = keys[plan.option]
        if self.trace is not None:
            alive = self.teammates.alive[i].sum(axis=1)
            self.trace.append(Decision(view.step, i, tuple(keys), plan.G, plan.option,
                                       arrivals, plan.predictions, alive, sets))  # fmt: skip
        if plan.kind == "task":
            return ("task", plan.task)
        if plan.kind == "fetch":
            return ("fetch", plan.task, plan.helper)
        return ("explore",)
