"""The rendezvous search: a group that waited at a goal for the rest of the team goes to
look for it.

In rendezvous with a sensing range, a robot standing at a goal that sees some teammates
there and the others nowhere knows the mission does not hold (it would see the whole team)
and that no one it can see is coming. After ``lone_wait`` steps it leaves to look for the
rest: first where it saw missing teammates settle, then at the other goals it knows, then
sweeping the workspace (:class:`~epistemica.sim.policies.explore.Explorer`). Everyone in
such a group knows the same, so the group leaves together. A searcher stops when it sees a teammate
settled where none stood when it left (the settle it then observes is its newest, and
wins). Each search doubles the robot's next wait: two groups that left at once and crossed
unseen would otherwise keep missing each other.

A group that holds a teammate that never searches (a greedy or stationary robot) must not
leave it: every other teammate has to come there in the end, and a group that leaves
crosses the ones that come. Everyone of the team's own level in a group counts its wait
from the step it stands still (the step its teammates see it settle), so the group leaves
at one step; a member still seen settling at that goal ``anchor_check`` steps later, and
until ``lone_wait`` steps after, is an *anchor*: the searcher goes back and waits there.
When it has stood there ``anchor_check`` steps without seeing an anchor settle (one that
only left later than the rest), it searches on.

A group that knows that a teammate it does not see has never heard of its goal knows that
teammate is not on its way: it waits ``unaware_wait`` steps instead of ``lone_wait``.

With ``meet`` (the planner's levels), searchers that see teammates outside the group they
left with have found them: all follow the lowest-numbered robot in sight to the goal they
see it settle at. Groups merged so leave their goal at different steps (each had doubled
its wait a different number of times); a teammate seen to leave a goal it had settled at
searches, so it is no anchor, or the group would hold itself back for good.

With ``hold`` (the planner's levels) an anchor outranks a find: a searcher that sees a
member of the group it left still settled at that goal ``anchor_check`` steps on goes back
to it even when it also sees teammates settled elsewhere. The anchor never moves, so the
team can only form at its goal; the others come there when they search.

With ``sighted`` (the planner's levels) a searcher looks, after the goals where it saw
missing teammates settle and before the other goals it knows, where it last saw a teammate
it does not see now, outside the group it left with (the newest sighting first): a
stationary teammate stands where it was seen, and a group that went elsewhere was last
seen on its way there. A sighting it has come within ``look`` of the sensing range of (or
that lies so near the goal it left) is looked at until the teammate is seen anew. A
meeting's leader that no longer sees any teammate outside its group has no one following
(those it met held to an anchor, or were heading for a goal they had found): it drops the
meeting and searches on, first where it last saw them.
"""

from __future__ import annotations

import numpy as np

from epistemica.sim.engine.events import STILL
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.explore import Explorer

__all__ = ["LastSightings", "RendezvousSearch"]


class RendezvousSearch:
    """Who searches, and where, for the robots of one trial.

    Parameters
    ----------
    scenario : Scenario
    spacing : float
        Cell spacing of the sweep (the discovery range).
    lone_wait : int
        Steps a group waits before its first search.
    look : float
        A goal counts as looked at from this fraction of the sensing range.
    anchor_check : int
        Steps after leaving from which a member of the group still seen settling at the
        goal is an anchor (0: never).
    unaware_wait : int, optional
        Steps a group waits instead when it knows that a teammate it does not see does
        not know of its goal (default ``lone_wait``: a level that does not reason about
        what teammates know).
    meet : bool, optional
        A searcher stops when it sees a teammate outside the group it left with, and a
        teammate it saw leave a goal it had settled at is no anchor (default False: only a
        teammate settled elsewhere, or newly at the goal it left, ends a search, and any
        member still seen settling is an anchor).
    hold : bool, optional
        An anchor outranks a find: a searcher that sees an anchor (above) goes back to it
        although it also sees teammates settled elsewhere (default False: the find ends
        the search).
    sighted : bool, optional
        Look where missing teammates were last seen before the other goals the robot
        knows, and drop a meeting nobody follows (default False: goals only, then the
        sweep; a leader leads a meeting to its end).
    """

    def __init__(
        self,
        scenario: Scenario,
        spacing: float,
        lone_wait: int,
        look: float,
        anchor_check: int,
        unaware_wait: int | None = None,
        meet: bool = False,
        hold: bool = False,
        sighted: bool = False,
    ) -> None:
        n = scenario.n_robots
        self.scenario, self.lone_wait, self.look = scenario, int(lone_wait), float(look)
        self.unaware_wait = self.lone_wait if unaware_wait is None else int(unaware_wait)
        self.anchor_check, self.meet, self.hold = int(anchor_check), bool(meet), bool(hold)
        # Without a sensing range nobody searches (``applies``): no sightings to keep.
        self.sightings = LastSightings(scenario, look) if sighted and self.applies() else None
        self.anchor = np.full(n, -1)  # the goal a robot waits at with anchors (-1: none)
        self.anchors = np.zeros((n, n), dtype=bool)  # who it waits with
        self.since = np.zeros(n, dtype=int)  # steps since the search started
        self.unseen = np.zeros(n, dtype=int)  # steps back at the goal not seeing an anchor
        self.sweep = Explorer(scenario.workspace, spacing, n)
        self.waiting = np.zeros(n, dtype=int)
        self.left = np.full(n, -1)  # the goal a searcher left (-1: not searching)
        self.group = np.zeros((n, n), dtype=bool)  # who stayed there with it
        self.searches = np.zeros(n, dtype=int)
        self.mark = np.zeros(n, dtype=int)  # settles it had seen when it left
        self.checked = np.zeros((n, scenario.n_goals), dtype=bool)
        self.last = np.full((n, 2), np.nan)  # each robot's own position a step before
        self.meeting = np.full(n, -1)  # the goal two groups that met head for (-1: none)
        self.leader = np.full(n, -1)  # whom a searcher that met teammates follows
        self.spot = np.full((n, n), -1)  # where it last saw each teammate settle, in sight
        self.roamed = np.zeros((n, n), dtype=bool)  # saw it leave that spot: it searches

    def applies(self) -> bool:
        """Whether the scenario calls for searching (rendezvous with a sensing range)."""
        return self.scenario.kind.gathers and self.scenario.sensing_range is not None

    def searchers(self, observations: Observations, robots: np.ndarray) -> np.ndarray:
        """``(len(robots),)`` which of ``robots`` search this step (state updated)."""
        s = self.scenario
        if not self.applies():
            return np.zeros(len(robots), dtype=bool)
        rows = np.arange(len(robots))
        pose = observations.poses[robots, robots, :2]
        d = np.hypot(*(pose[:, None] - s.goals[None]).transpose(2, 0, 1))
        own = np.where(d.min(axis=1) <= s.success_radius, d.argmin(axis=1), -1)
        # A robot counts its wait from the step it stands still, the step its teammates
        # see it settle: the group's waits then start, and end, together.
        still = np.hypot(*(pose - self.last[robots]).T) < STILL
        self.last[robots] = pose
        at, fresh, count = self._settles(observations, robots)
        seen = observations.seen[robots].copy()
        seen[rows, robots] = False
        everyone = seen.sum(axis=1) == s.n_robots - 1
        together = (~seen | (at == own[:, None])).all(axis=1)  # all in sight stand here
        left, group = self.left[robots], self.group[robots]
        # Found: a teammate settled at another goal, or one that settled at the goal the
        # searcher left after it left (a newcomer there).
        elsewhere = seen & (at >= 0) & (at != left[:, None])
        newcomer = fresh & ~group & (at == left[:, None])
        found = (elsewhere | newcomer).any(axis=1)
        if self.meet:
            found |= self._meet(observations, robots, own, still, seen, group)
        if self.hold:  # an anchor outranks any find or meeting (``_watch`` takes it)
            held = self._anchored(observations, robots) | (self.anchor[robots] >= 0)
            found &= ~held
            self.meeting[robots[held]], self.leader[robots[held]] = -1, -1
        searching = (left >= 0) & ~found
        waiting = (own >= 0) & ~everyone & together & ~searching
        self.waiting[robots] = np.where(waiting, self.waiting[robots] + still, 0)
        patience = np.where(
            self._unaware(observations, robots, own, seen, waiting),
            self.unaware_wait,
            self.lone_wait,
        )
        start = self.waiting[robots] >= patience * 2 ** self.searches[robots]
        self.searches[robots] += start
        if start.any():
            self.sweep.visited[robots[start]] = False  # a new search sweeps anew
            self.checked[robots[start]] = False
            self.group[robots[start]] = seen[start] & (at[start] == own[start, None])
            self.mark[robots[start]] = count[start]
        self.left[robots] = np.where(start, own, np.where(searching, left, -1))
        self.meeting[robots] = np.where(searching, self.meeting[robots], -1)
        self.leader[robots] = np.where(searching, self.leader[robots], -1)
        if self.meet:
            self._roam(observations, robots, own < 0)
        self._watch(observations, robots, start)
        return (self.left[robots] >= 0) | (self.anchor[robots] >= 0)

    def _meet(self, observations: Observations, robots, own, still, seen, group) -> np.ndarray:
        """``(len(robots),)`` which searchers end their search where they met other
        teammates (in sight, ``seen``, outside the ``group`` each left with).

        From the step a searcher first sees such a teammate it follows, every step, the
        lowest-numbered robot in its sight (itself included): that *leader* heads for the
        goal nearest its own position among those it knows; the others steer for where
        they see it and, once they see it settle, for that goal. Robots that know
        different goals, or see the leader where it is not (noisy sensing), would each
        compute a different "goal nearest the leader"; a settle is seen as it is. A
        follower that loses sight of its leader keeps what it last saw. Its search ends
        once it stands still on the goal, where its settle and theirs are the newest each
        has seen. With ``sighted`` a leader that sees none of the teammates outside its group
        (nobody follows it) drops the meeting and searches on."""
        goals, meeting = self.scenario.goals, self.meeting[robots]
        leaders = self.leader[robots]
        met = (self.left[robots] >= 0) & ((leaders >= 0) | (seen & ~group).any(axis=1))
        for row in np.flatnonzero(met):
            robot = int(robots[row])
            if seen[row].any():
                leaders[row] = min(robot, int(np.argmax(seen[row])))
            elif leaders[row] < 0:
                leaders[row] = robot
            leader = int(leaders[row])
            alone = not (seen[row] & ~group[row]).any()  # none of those it met in sight
            if leader == robot and alone and self.sightings is not None:
                leaders[row], meeting[row] = -1, -1  # a meeting nobody follows: search on
                continue
            if leader == robot:
                d = np.hypot(*(goals - observations.poses[robot, robot, :2]).T)
                d[~observations.known_goals[robot]] = np.inf
                meeting[row] = int(np.argmin(d))
            elif seen[row, leader]:
                settle = -1 if observations.settles is None else observations.settles[robot, leader]
                meeting[row] = settle  # -1 while it moves: follow it
        self.meeting[robots], self.leader[robots] = meeting, leaders
        return (meeting >= 0) & (meeting == own) & still

    def _roam(self, observations: Observations, robots, travelling) -> None:
        """Who each robot has seen leave a goal it had seen them settle at, since it last
        stood at a goal or searched (``travelling`` robots forget). A teammate that never
        searches never leaves its goal; one seen to leave is a searcher, no anchor: groups
        merged by a meeting leave at different steps (their waits doubled a different
        number of times), and would otherwise hold one another back for good."""
        if observations.settles is None:
            return
        robots = np.asarray(robots)
        settles = observations.settles[robots]
        seen = observations.seen[robots]
        spot = self.spot[robots]
        left = seen & (spot >= 0) & (settles != spot)
        idle = travelling & (self.left[robots] < 0) & (self.anchor[robots] < 0)
        self.roamed[robots] = (self.roamed[robots] | left) & ~idle[:, None]
        self.spot[robots] = np.where(seen, settles, spot)

    def _anchored(self, observations: Observations, robots) -> np.ndarray:
        """``(len(robots),)`` which searchers ``_watch`` makes wait with an anchor this
        step: a member of the group each left, seen settled at that goal (and never seen
        to leave it) ``anchor_check`` to ``lone_wait`` steps after it left."""
        out = np.zeros(len(robots), dtype=bool)
        if self.anchor_check == 0 or observations.settles is None:
            return out
        robots = np.asarray(robots)
        left, since = self.left[robots], self.since[robots] + 1  # ``_watch`` counts it next
        timely = (left >= 0) & (self.anchor[robots] < 0)
        timely &= (since >= self.anchor_check) & (since <= self.lone_wait)
        settles = observations.settles[robots]
        stayed = self.group[robots] & (settles == left[:, None]) & ~self.roamed[robots]
        return timely & stayed.any(axis=1)

    def _unaware(self, observations: Observations, robots, own, seen, waiting) -> np.ndarray:
        """``(len(robots),)`` which waiting robots know that a teammate they do not see
        does not know of the goal they wait at: that teammate is not on its way."""
        out = np.zeros(len(robots), dtype=bool)
        knowledge = observations.knowledge
        if knowledge is None or self.unaware_wait == self.lone_wait:
            return out
        for row in np.flatnonzero(waiting):
            robot = int(robots[row])
            for teammate in np.flatnonzero(~seen[row]):
                if (
                    teammate != robot
                    and not knowledge.knows_goals((robot, int(teammate)))[own[row]]
                ):
                    out[row] = True
                    break
        return out

    def _watch(self, observations: Observations, robots: np.ndarray, start: np.ndarray) -> None:
        """A searcher that sees a member of the group it left still settle at that goal,
        ``anchor_check`` steps on, goes back to wait with it; one waiting there that
        sees no anchor settle for ``anchor_check`` steps searches on."""
        if self.anchor_check == 0 or observations.settles is None:
            return
        k = self.anchor_check
        for row, robot in enumerate(robots):
            self.since[robot] = 0 if start[row] else self.since[robot] + 1
            settles = observations.settles[robot]
            goal = self.anchor[robot]
            if goal >= 0:
                pose = observations.poses[robot, robot, :2]
                back = np.hypot(*(pose - self.scenario.goals[goal])) <= self.scenario.success_radius
                anchors = self.anchors[robot] & ~self.roamed[robot]
                seen = (settles[anchors] == goal).any()
                self.unseen[robot] = self.unseen[robot] + 1 if back and not seen else 0
                if self.unseen[robot] >= k:
                    self.left[robot], self.anchor[robot] = goal, -1
                continue
            goal = self.left[robot]
            if goal < 0 or not k <= self.since[robot] <= self.lone_wait:
                continue
            stayed = self.group[robot] & (settles == goal) & ~self.roamed[robot]
            if stayed.any():
                self.anchor[robot], self.anchors[robot], self.unseen[robot] = goal, stayed, 0

    def _settles(self, observations: Observations, robots: np.ndarray):
        """Where each robot last saw each teammate settle (a noisy view of a position
        cannot tell "at my goal" from "near it"; a settle event can), which of those are
        new since it left, and how many settles it has seen."""
        n = self.scenario.n_robots
        at = np.full((len(robots), n), -1)
        fresh = np.zeros((len(robots), n), dtype=bool)
        count = np.zeros(len(robots), dtype=int)
        if observations.knowledge is None:
            return at, fresh, count
        for row, robot in enumerate(robots):
            events = observations.knowledge.settled((robot,))  # newest first
            count[row] = len(events)
            for teammate, goal in reversed(events):
                at[row, teammate] = goal  # oldest first: the newest wins
            for teammate, _ in events[: max(len(events) - self.mark[robot], 0)]:
                fresh[row, teammate] = True
        return at, fresh, count

    def target(self, observations: Observations, robot: int) -> np.ndarray | None:
        """Where a searcher heads: the goals where it last saw a missing teammate settle,
        then the other goals it knows, then the nearest cell not swept; None when all
        are searched."""
        s, pose = self.scenario, observations.poses[robot, robot]
        if self.meeting[robot] >= 0:
            return s.goals[self.meeting[robot]]
        if self.leader[robot] >= 0:  # following a leader not yet settled (a leader
            return observations.poses[robot, self.leader[robot], :2]  # has a meeting)
        if self.anchor[robot] >= 0:
            return s.goals[self.anchor[robot]]
        self.sweep.visit(pose[None, :2], [robot])
        distance = np.hypot(*(s.goals - pose[:2]).T)
        self.checked[robot] |= distance <= self.look * s.sensing_range
        clues = np.zeros(s.n_goals, dtype=bool)
        if observations.knowledge is not None:
            for teammate, goal in observations.knowledge.settled((robot,)):
                if teammate != robot and not self.group[robot, teammate]:
                    clues[goal] = True
        # The team can only be waiting at a goal: first where missing teammates were
        # seen to settle, (``sighted``) where they were last seen, then the other goals
        # the robot knows, then the whole workspace.
        unchecked = ~self.checked[robot]
        for candidates in (clues & unchecked, None, observations.known_goals[robot] & unchecked):
            if candidates is None:
                where = self.sightings and self.sightings.next(
                    observations, robot, self.group[robot], self.left[robot]
                )
                if where is not None:
                    return where
            elif candidates.any():
                goals = np.flatnonzero(candidates)
                return s.goals[goals[np.argmin(distance[goals])]]
        return self.sweep.target(robot, pose)


class LastSightings:
    """Where each searcher last saw the teammates it misses, and which of those sightings
    it has looked at (``RendezvousSearch(sighted=True)``).

    Parameters
    ----------
    scenario : Scenario
    look : float
        A sighting counts as looked at from this fraction of the sensing range.
    """

    def __init__(self, scenario: Scenario, look: float) -> None:
        n = scenario.n_robots
        self.scenario, self.reach = scenario, float(look) * float(scenario.sensing_range)
        self.looked = np.full((n, n), -1)  # the sighting of each teammate looked at (its step)

    def next(
        self, observations: Observations, robot: int, group: np.ndarray, left: int = -1
    ) -> np.ndarray | None:
        """Where ``robot`` last saw a teammate it does not see now, outside its ``group``
        (those it left goal ``left`` with), the newest such sighting it has not looked at
        (the nearest among equally new ones); None when there is none. A sighting within
        ``look`` of the sensing range of the robot, or of the goal it left, is looked at.

        Examples
        --------
        >>> from epistemica.sim.engine.sensing import Observations
        >>> scenario = Scenario.paper("rendezvous", 3, 3, seed=0, sensing_range=4.0)
        >>> sightings = LastSightings(scenario, 0.5)
        >>> poses = np.zeros((3, 3, 3))
        >>> poses[0, 1, :2], poses[0, 2, :2] = (20.0, 0.0), (0.0, 30.0)  # r1's last sightings
        >>> seen, group = np.zeros((3, 3), bool), np.zeros(3, bool)
        >>> last = np.array([[5, 3, 7], [-1, 5, -1], [-1, -1, 5]])    # r3 seen later than r2
        >>> def at(step):
        ...     return Observations(step, poses, seen, last, seen, seen)
        >>> sightings.next(at(8), 0, group).tolist()       # r3's sighting, the newer one
        [0.0, 30.0]
        >>> poses[0, 0, :2] = (0.0, 28.5)                  # r1 comes within 0.5 x 4 m of it
        >>> sightings.next(at(9), 0, group).tolist()       # looked at: r2's sighting next
        [20.0, 0.0]
        """
        s = self.scenario
        where = observations.poses[robot, :, :2]
        last = observations.last_seen[robot]
        missing = (last > self.looked[robot]) & ~observations.seen[robot] & ~group
        missing[robot] = False
        near = np.hypot(*(where - where[robot]).T) <= self.reach
        if left >= 0:  # the goal it left was looked at as it waited there
            near |= np.hypot(*(where - s.goals[left]).T) <= self.reach
        self.looked[robot] = np.where(missing & near, last, self.looked[robot])
        missing &= ~near
        if not missing.any():
            return None
        newest = np.flatnonzero(missing & (last == last[missing].max()))
        distance = np.hypot(*(where[newest] - where[robot]).T)
        return where[newest[np.argmin(distance)]]
