"""The constants of the collaborative levels (:mod:`epistemica.sim.policies.collaborative_levels`):
one frozen set for every collaborative mission, which a mission file's ``policy`` lines
change.

Examples
--------
>>> CollaborativeParameters().patience, CollaborativeParameters(patience=30).patience
(60, 30)
>>> try:
...     CollaborativeParameters().replace(speed=3)
... except ValueError as exc:
...     print(str(exc).splitlines()[0])
unknown collaborative parameter 'speed'
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["CollaborativeParameters"]


@dataclass(frozen=True)
class CollaborativeParameters:
    """Every constant of the collaborative levels, one set for every mission (chosen on
    tuning seeds 1000-1199: docs/results.md, "Collaborative tasks found while exploring").

    Attributes
    ----------
    lane_factor : float
        Lane spacing of the sweep, in sensing ranges (2 leaves no gap between lanes).
    patience, hold : int
        Steps a robot waits at a task before exploring again; steps before it may return.
    join_bonus : float
        ``rules-first``: metres a task seems nearer per teammate seen waiting there.
    intercept_limit : int
        ``rules``: steps a robot looks for a teammate it fetches before it gives up on it.
    wait_horizon : int
        ``rules``: a teammate whose predicted sweep passes within sight of the task in this
        many steps is waited for rather than fetched (0: only one in sight of it now).
        With teammates predicted as :class:`TeammateModel` does, 0 / 10 / 20 / 40 took
        76.4 / 76.5 / 80.4 / 93.4 steps at 3 robots, 85.5 / 85.6 / 87.1 / 89.6 at 5 and
        74.0 / 75.0 / 75.3 / 75.6 at 8 (tuning seeds 1000-1199): a fetcher brings the
        teammate sooner than its sweep would.
    fetch_memory : int
        ``rules``: only a teammate seen in the last ``fetch_memory`` steps is fetched (where
        others are is a guess). A teammate never seen counts as seen at the start, on its
        way to its sweep (the convention says where that begins): fetching only teammates
        really seen took 95.5 / 92.6 / 81.1 steps against 86.9 / 91.1 / 78.4 at 3 / 5 / 8
        robots on tuning seeds 1000-1199.
    seek : bool
        ``rules``: the only robot it knows knows of a task, with nobody to fetch, explores
        on (it meets teammates to fetch) rather than waiting at the task.
    backed_patience : int
        ``rules``: steps a robot waits at a task while it knows a teammate that knows the
        task is out fetching or looking for helpers for it (``patience`` otherwise).
    stand_in : bool
        ``rules``: a knower of a task not among the ones it would send goes in place of
        each chosen teammate whose place it does not know (not seen for ``fetch_memory``
        steps): that teammate's own view, and so its choice, may differ.
    sweep_memory : int
        ``rules``: a teammate not seen for longer than ``fetch_memory`` (at most this many
        steps) is still fetched when the robot knows it is on its sweep: it knows of no
        open task the robot knows that teammate knows, and its predicted sweep since it
        was last seen passed in sight of no open task the robot knows (0: off).
    meet_ahead : bool
        ``rules``: a fetcher goes to the first place of the teammate's predicted sweep it
        can reach in time (:func:`~epistemica.sim.policies.collaborative_sweep.meeting_point`),
        rather than to where the teammate is now, and picks the teammate it brings to the
        task soonest.
    complete_first : bool
        ``rules``: a robot assigns the tasks that enough robots it knows know of (itself
        included) before those that too few know of, rather than in index order.
    rejoin : bool
        ``rules``: news of one more robot that knows of a task renews the patience of a
        robot waiting there, and a task a robot put on hold is open to it again as soon as
        it knows of more robots that know of it than when it gave up waiting.
    stale_after : int
        ``rules``: a robot presumes a task done once at least as many teammates as it
        needs have been known to know of it for this many steps while the robot has not
        seen it open for as long (0: off).
    verify : bool
        ``rules``: a robot that knows of every task of the mission and has nothing to do
        goes to see the nearest task it presumes done (``stale_after``) rather than
        exploring: teammates known to know of a task may have been busy elsewhere, and
        nothing is left to find.
    seek_limit : int
        ``rules``: a robot that began looking for helpers for a task (``seek``) this many
        steps ago waits at the task instead until its patience there runs out, and looks
        anew after its hold (0: it looks on: robots that each know a task nobody else is
        known to know of, on parallel sweeps, may never meet).
    fetch_together : bool
        ``rules``: the knower nearest a task too few know of, which would wait there while
        another knower fetches a teammate, goes for that teammate too when no other
        teammate that does not know of the task is near enough to see it wait
        (``watch_range``; with three robots, two knowers and the one fetched, none is).
    watch_range : float
        ``fetch_together``: a teammate counts as one that may see the knower wait only if
        predicted within this many sensing ranges of the task (measured: aif.md §6h).
    join_busy : bool
        ``rules``: a knower of a task too few know of, with no free teammate it knows where
        to find, goes to the nearest task it expects teammates at (sent there by its own
        assignment) rather than looking for helpers: once that task is done they are free
        and in its sight, to be told. Paired on tuning seeds 1000-1199 at 3 / 5 / 8 robots:
        -2.5 +- 0.8 / -0.5 +- 0.7 / -0.2 +- 0.1 steps; on 1200-1399: -3.4 +- 0.7 / -0.5 +-
        0.3 / +0.3 +- 0.3.
    soonest : bool
        ``rules``, ``rules-shared``: tasks go to robots coalition by coalition, first the
        task whose ``needs`` nearest free knowers assemble soonest (the farthest of them is
        nearest), rather than in index order (a robot 30 m off no longer walks past a task
        teammates wait at for one that comes first in the mission). Paired for ``rules``
        at 3 / 5 / 8 robots, on tuning seeds 1000-1199: -1.8 +- 0.8 / -0.7 +- 0.9 / -0.3 +-
        0.9 steps; on 1200-1399: -1.2 +- 0.6 / -2.1 +- 0.8 / -2.1 +- 0.9.
    resume : bool
        ``rules``, ``rules-shared``: a teammate seen off its sweep and moving makes for the
        waypoint its motion points at, then sweeps on
        (:class:`~epistemica.sim.policies.collaborative_teammates.TeammateModel`), rather than being
        put on the nearest point of its sweep.
    particles : int
        ``rules``, ``rules-shared``: a teammate never seen started at one of a grid of
        ``particles`` x ``particles`` starts, less those that would have put it in sight
        (0: it reached its sweep after half the workspace's side). Prediction error of
        unseen teammates, median on tuning seeds 1000-1039 at 3 / 5 / 8 robots: 12.1 /
        13.9 / 17.5 m with neither, 8.2 / 10.2 / 12.4 m with both.

    The geometry of sight and sweeps (set once, before any tuning; not tuned since):

    off_sweep : float
        ``rules``: a teammate last seen farther than this many sensing ranges from its
        sweep is off it (at a task): where it resumed is unknown (``sweep_memory``).
    sight_fraction : float
        Sensing ranges within which a robot counts on being seen: where a fetcher meets a
        teammate on its sweep (``meet_ahead``) and whom ``wait_horizon`` waits for.
    horizon_step : int
        ``wait_horizon``: steps between the predicted places it checks (at least 1).
    lost_range : float
        ``meet_ahead``: a fetcher this many sensing ranges from where it predicts the
        teammate, without seeing it, gives up on it (it left its sweep).
    waypoint_reach : float
        Metres within which a robot has reached the next waypoint of its sweep.
    rejoin_gap : float
        ``resume``: metres within which a teammate seen is back on its sweep.
    still_fraction : float
        ``resume``: a teammate seen to move less than this fraction of its top speed in a
        step is standing, and shows no waypoint it makes for.
    heading_slack : float
        ``resume``: waypoints whose direction is within this cosine of the teammate's
        motion are the one it makes for (the same point on later laps of the sweep).

    The planning levels (``first``, ``second``, ``third`` and their ablations,
    :mod:`epistemica.sim.policies.collaborative_planning`; times in units of the workspace's
    crossing time, side / mean speed). Each option was measured on tuning missions only;
    the tables (success, median / mean steps, paired intervals) are in docs/aif.md §6h,
    pass by pass, the last in "Fresh missions 600-799" (tuning-stream seeds 600-799).

    plan_temperature : float
        The precision ``tau`` of :class:`~epistemica.aif.task_planning.TaskPlanner` (it
        also scales the convention and commitment terms).
    plan_repair : float
        The cost of a task too few come to (``fail``).
    plan_explore : float
        Time saved per unknown task by one more explorer, as a fraction of ``fail``
        shared by the team.
    plan_commitment : float
        Nats a robot pays to change the option it chose at its last plan.
    plan_convention : float
        Weight (nats) of the shared convention's choice in the robot's own (at 2 the
        convention overrides fetching).
    plan_credit : float
        Credit (0-1) for a robot that comes to a task too few robots come to (without it a
        task needing three is never started: one helper saves nothing until a second comes).
    plan_recruit : bool
        The convention's prior gives fetching a teammate the weight it gives exploring,
        rather than the 5 % spread of an option it never takes (which cost a fetch ~5 nats:
        docs/results/collaborative_wrong_decision.md).
    plan_timed : bool
        The credit of a robot that comes to a short-handed task falls with its arrival
        (``1 - a / fail`` of its share), so fetches rank by meeting time.
    plan_quorum : int
        The fewest robots at a short-handed task that earn credit (1: any).
    plan_later : float
        Crossings by which a robot that chooses another option still comes to a task (the
        baseline its option saves time against; 0: it never comes). Off.
    plan_rendezvous : bool
        Going to a task is valued by the completion it makes likelier under the teammates'
        predicted choices alone; ``plan_credit`` goes only to the teammate a fetch brings.
    plan_mission : bool
        A fetch is charged what its helper's other tasks lose.
    plan_pool : bool
        Credit for the robots at a short-handed task counts only while enough of the
        others are predicted free to make up the number (2.5 times the decision time).
    plan_fetchers : bool
        Teammates' predicted choices include fetching (chain ``(i, l, h)``).
    plan_rollout : float
        Horizon (crossings) of a rollout over fetch chains (0: off; aif.md §6h, fifth pass).
    plan_sighted : bool
        A teammate seen with an open task in its sensing range knows of it. Off.
    plan_knowers : bool
        Coming to a task earns ``plan_credit`` only when as many robots as it needs know
        of it (:class:`~epistemica.aif.task_planning.TaskPlanner`'s ``knowers``). Off.
    plan_insight : bool
        A teammate in sight is met where it is seen, not on its sweep. Off (tuning split).
    plan_retry, plan_lost, plan_missed : bool, bool, int
        A teammate a robot gave up fetching is fetched again once seen (``plan_retry``), not
        for any other task till then (``plan_lost``), nor one never seen whose every start is
        ruled out, nor (``plan_missed``, on (1): aif.md §6h 1600-1999) one seen before whose
        predicted place is ``lost_range`` from it, unseen (2: for ``fetch_memory`` steps).
    plan_hail, plan_hailed, plan_chase : bool, bool, int
        Fetch only where a ``heads to`` event tells (``plan_hail``). A teammate hailed for
        a task (in sight, within hailing distance) still not known to know of it is not
        fetched for it again: at once (``plan_hailed``), or, with no ``heads to`` event,
        ``plan_chase`` steps after the first hail (0: off; aif.md §6h, missions 1000-1199).
    plan_told : bool
        Without a ``heads to`` event, a teammate is fetched for a task only if it is
        predicted in sight where the fetcher re-enters the found event's reach of the task
        or stands at it: the only ways the fetch can tell it. On (fresh missions 300-399).
    plan_back : bool
        Without a ``heads to`` event, a fetcher that has hailed its helper goes on to the
        task (where it can tell it), not back to the helper once out of hailing distance.
    plan_hold : bool
        The rules' patience for the planner (:meth:`CollaborativePolicy.unheld`). On with
        ``plan_told`` (it ends standoffs at tasks; fresh missions 300-399).
    plan_spread, plan_watched : bool, int
        A never-seen teammate is found only with the share of its starts in sight of the
        meeting (off). ``stale_after`` counts a knower from the earliest step it can have
        reached the task since seen away (1, on: 1200-1599), unless it can have done it first (2).
    plan_waiters : int
        A teammate seen standing still at an open task knows of it, is met where it stands,
        and a fetch of it for another task is charged what that task loses; with 1, not 2,
        it is also predicted to wait there (0: off).
    plan_presumed : bool
        A task a robot presumed done (``stale_after``) and then found open is taken to be
        presumed done by every teammate not seen standing at it: not predicted to come.
    """

    lane_factor: float = 2.0
    patience: int = 60
    hold: int = 40
    join_bonus: float = 10.0
    intercept_limit: int = 40
    wait_horizon: int = 0
    fetch_memory: int = 40
    seek: bool = True
    backed_patience: int = 150
    stand_in: bool = False
    sweep_memory: int = 0
    meet_ahead: bool = False
    complete_first: bool = True
    rejoin: bool = True
    stale_after: int = 20
    seek_limit: int = 20
    verify: bool = True
    resume: bool = True
    particles: int = 12
    fetch_together: bool = True
    watch_range: float = 3.0
    join_busy: bool = True
    soonest: bool = True
    off_sweep: float = 0.5
    sight_fraction: float = 0.8
    horizon_step: int = 5
    lost_range: float = 0.5
    waypoint_reach: float = 1.0
    rejoin_gap: float = 1.0
    still_fraction: float = 0.3
    heading_slack: float = 0.01
    plan_temperature: float = 0.1
    plan_repair: float = 2.0
    plan_explore: float = 0.25
    plan_commitment: float = 1.0
    plan_convention: float = 1.0
    plan_credit: float = 1.0
    plan_recruit: bool = True
    plan_timed: bool = False
    plan_quorum: int = 1
    plan_later: float = 0.0
    plan_retry: bool = True
    plan_rendezvous: bool = False
    plan_mission: bool = False
    plan_pool: bool = False
    plan_fetchers: bool = False
    plan_rollout: float = 0.0
    plan_sighted: bool = False
    plan_knowers: bool = False
    plan_insight: bool = False
    plan_hail: bool = False
    plan_lost: bool = True
    plan_hailed: bool = False
    plan_chase: int = 0
    plan_told: bool = True
    plan_back: bool = False
    plan_hold: bool = True
    plan_spread: bool = False
    plan_watched: int = 1
    plan_waiters: int = 0
    plan_presumed: bool = False
    plan_missed: int = 1

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value >= 0):
                raise InvalidArgumentError(
                    f"{f.name} must be a finite number >= 0, got {value!r}",
                    hint="see CollaborativeParameters",
                )
        if self.lane_factor <= 0:
            raise InvalidArgumentError("lane_factor must be > 0", hint="2.0")
        if self.horizon_step < 1:
            raise InvalidArgumentError("horizon_step must be >= 1", hint="5")
        top = {"plan_waiters": 2, "plan_presumed": 1, "plan_watched": 2, "plan_missed": 2}
        if self.plan_quorum < 1 or any(getattr(self, k) not in range(top[k] + 1) for k in top):
            raise InvalidArgumentError(f"plan_quorum must be >= 1, and each of {top} 0 to it")

    def replace(self, **changes) -> CollaborativeParameters:
        unknown = set(changes) - {f.name for f in fields(self)}
        if unknown:
            raise InvalidArgumentError(
                f"unknown collaborative parameter {sorted(unknown)[0]!r}",
                hint=f"one of {', '.join(f.name for f in fields(self))}",
            )
        return replace(self, **changes)
