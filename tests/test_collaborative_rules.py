"""The rules of the collaborative levels, each on a small scene worked by hand
(sim/policies/collaborative_levels.py, sim/policies/collaborative_sweep.py)."""

import numpy as np
import pytest

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.events import World, firings, observer_indices
from epistemica.sim.engine.joint import JointView
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.policies.collaborative_levels import (
    FETCHING,
)
from epistemica.sim.policies.collaborative_parameters import CollaborativeParameters
from epistemica.sim.policies.collaborative_sweep import Route, meeting_point
from epistemica.sim.policies.levels import make_level

LANE = Route(np.array([[5.0, 0.0], [5.0, 30.0], [15.0, 30.0]]))  # up x = 5, then east


def _policy(scenario, **changes):
    policy = make_level("collaborative", "rules", CollaborativeParameters().replace(**changes))
    policy.start(scenario)
    return policy


def _view(k: TeamKnowledge, poses, step, since=None, open_seen=None, last_seen=None) -> JointView:
    """What the robots have at ``step``: every robot sees every other now (unless
    ``last_seen`` says otherwise), and has known what it knows since step 0."""
    poses = np.asarray(poses, dtype=float)
    n = len(poses)
    aware = np.array(
        [[k.knows_goals((i,) if i == j else (i, j)) for j in range(n)] for i in range(n)]
    )
    since = np.where(aware, 0, -1) if since is None else np.asarray(since)
    open_seen = np.full((n, k.m), -1) if open_seen is None else np.asarray(open_seen)
    last_seen = np.full((n, n), step) if last_seen is None else np.asarray(last_seen)
    estimates = np.repeat(poses[None, :, :2], n, axis=0)
    return JointView(step, poses, estimates, last_seen, k, aware, since, open_seen)


# -- where a robot meets a teammate on its sweep ----------------------------------------------


def test_the_meeting_point_on_a_lane_is_the_first_step_it_can_reach():
    # the teammate goes up x = 5 from (5, 0) at 1 m a step; the robot at (15, 20) moves
    # 1 m a step: the first tau with sqrt(10^2 + (20 - tau)^2) <= tau is 12.5 -> 13
    tau, place = meeting_point(np.array([15.0, 20.0]), 1.0, LANE, 0.0, 1.0, 0.0, 40)
    assert tau == 13 and place.tolist() == [5.0, 13.0]
    # seen from 5 m (reach 5): sqrt(100 + (20 - tau)^2) - 5 <= tau  <=>  tau >= 10
    tau, place = meeting_point(np.array([15.0, 20.0]), 1.0, LANE, 0.0, 1.0, 5.0, 40)
    assert tau == 10 and place.tolist() == [5.0, 10.0]
    # already in reach: now, where it is
    tau, place = meeting_point(np.array([6.0, 3.0]), 1.0, LANE, 3.0, 1.0, 2.0, 40)
    assert tau == 0 and place.tolist() == [5.0, 3.0]
    # a teammate as fast, 10 m ahead along the lane, is not caught in 20 steps
    assert meeting_point(np.array([5.0, 0.0]), 1.0, LANE, 10.0, 1.0, 0.0, 20) is None


def test_a_route_measures_arc_length_and_distance():
    assert LANE.at(35.0).tolist() == [10.0, 30.0]  # 30 m up, 5 m east
    assert LANE.along([-1.0, 100.0]).tolist() == [[5.0, 0.0], [15.0, 30.0]]  # clipped
    assert LANE.project(np.array([8.0, 12.0])) == 12.0
    assert LANE.gap(np.array([8.0, 12.0])) == 3.0


# -- tasks presumed done -------------------------------------------------------------


def _two_robot_scene(needs=(2,)):
    return CollaborativeScenario(
        [[2, 2, 0], [4, 2, 0], [6, 2, 0]], [[20, 20]], needs, workspace=30.0, sensing_range=7.0
    )


@pytest.mark.parametrize(
    ("step", "teammates", "open_seen", "presumed"),
    [
        (30, (1, 2), -1, True),  # two teammates have known it since 5: 5 <= 30 - 20
        (24, (1, 2), -1, False),  # only 19 steps
        (30, (1,), -1, False),  # one teammate cannot do a task that needs two
        (30, (1, 2), 15, False),  # robot 0 saw it open at 15, after 30 - 20
    ],
)
def test_a_task_enough_teammates_knew_of_long_enough_is_presumed_done(
    step, teammates, open_seen, presumed
):
    s = _two_robot_scene()
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((3, 1), dtype=bool))
    policy = _policy(s, stale_after=20)
    since = np.full((3, 3, 1), -1)
    since[0, 0, 0] = 5
    for j in teammates:
        since[0, j, 0] = 5
    view = _view(k, s.starts, step, since=since, open_seen=np.full((3, 1), open_seen))
    assert policy.presumed_done(view, 0).tolist() == [presumed]


@pytest.mark.parametrize(("tasks", "verify", "steer"), [(1, True, 0), (1, False, -1),
                                                        (2, True, -1)])  # fmt: skip
def test_a_robot_with_nothing_left_to_find_goes_to_see_a_task_it_presumes_done(
    tasks, verify, steer
):
    # r1 presumes t1 done (r2 and r3 have known of it since step 5, it has not seen it
    # open), so it has nothing to do. When t1 is the mission's only task, nothing is left
    # to find: it goes to see t1 (teammates that knew of it may have been busy elsewhere).
    # With a second task it has not found yet, it explores.
    s = CollaborativeScenario(
        [[2, 2, 0], [4, 2, 0], [6, 2, 0]], [[20, 20], [28, 2]][:tasks], (2,) * tasks,
        workspace=30.0, sensing_range=7.0,
    )  # fmt: skip
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((3, tasks), dtype=bool))
    k.discover(0, np.array([True, True, True]))
    since = np.full((3, 3, tasks), -1)
    since[0, :, 0] = 5
    policy = _policy(s, stale_after=20, verify=verify)
    view = _view(k, s.starts, 30, since=since, open_seen=np.full((3, tasks), -1))
    assert policy.presumed_done(view, 0)[0]
    assert int(policy.plan(view)[1][0]) == steer


# -- tasks enough robots know of come first --------------------------------------------------


def _three_robots_knowing(starts, tasks, needs, knowers):
    """Three robots at ``starts`` and tasks at ``tasks``; task ``t`` found by the robots
    ``knowers[t]`` (a mask) together, so each of them knows who else knows it."""
    s = CollaborativeScenario(starts, tasks, needs, workspace=30.0, sensing_range=7.0)
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((3, len(tasks)), dtype=bool))
    for t, mask in enumerate(knowers):
        k.discover(t, np.array(mask))
    return s, k


def test_a_robot_joins_the_task_its_teammates_expect_it_at():
    # r1 knows t1 (needs 2) alone, and t2 (needs 3) with r2 and r3, who know only t2 and
    # that r1 knows it: they expect r1 at t2. In index order r1 would deal with t1 first
    # (too few know: it fetches or waits there); completable tasks first, it goes to t2.
    # (`soonest` off: it would put t2 first for another reason, its coalition is at hand.)
    s, k = _three_robots_knowing(
        [[5, 15, 0], [25, 5, 0], [27, 7, 0]], [[3, 16], [28, 5]], (2, 3),
        [[True, False, False], [True, True, True]],
    )  # fmt: skip
    for complete_first, r1 in ((True, {1}), (False, {0, FETCHING})):
        policy = _policy(s, complete_first=complete_first, soonest=False)
        _, steer_to = policy.plan(_view(k, s.starts, 10))
        assert int(steer_to[0]) in r1
        assert int(steer_to[1]) == int(steer_to[2]) == 1  # r2 and r3 go to t2 either way


def test_a_knower_with_nobody_free_to_fetch_joins_the_teammates_busy_elsewhere():
    # r1 alone knows t2 (needs 2); all three know t1 (needs 2), and r2 and r3, nearer,
    # go there. Nobody is free to fetch for t2: with `join_busy` r1 goes to t1, where r2
    # and r3 will be free and in its sight once t1 is done; without it, it looks for
    # helpers (explores).
    s, k = _three_robots_knowing(
        [[10, 20, 0], [22, 6, 0], [27, 8, 0]], [[25, 5], [5, 25]], (2, 2),
        [[True, True, True], [True, False, False]],
    )  # fmt: skip
    for join_busy, r1 in ((True, 0), (False, -1)):
        policy = _policy(s, join_busy=join_busy)
        targets, steer_to = policy.plan(_view(k, s.starts, 10))
        assert steer_to.tolist() == [r1, 0, 0]
        assert (targets[0].tolist() == [25.0, 5.0]) == join_busy


def test_the_coalition_that_assembles_soonest_goes_first():
    # All three know t1 (25, 25) and t2 (5, 5), each needing two. In index order t1 goes
    # first to its two nearest, r3 (7 m off) and r1 (28 m; r2 ties and comes later), and
    # r2 is left alone with t2. With `soonest` t2 goes first, to r1 and r2 beside it (the
    # farther is 1.4 m off, against 28 m for t1's pair), and r3 is left alone with t1.
    # (`join_busy` off: the one left alone would join the pair, busy at the other task.)
    s, k = _three_robots_knowing(
        [[4, 6, 0], [6, 4, 0], [20, 20, 0]], [[25, 25], [5, 5]], (2, 2),
        [[True, True, True], [True, True, True]],
    )  # fmt: skip
    for soonest, pair, alone in ((True, (0, 1), 2), (False, (0, 2), 1)):
        policy = _policy(s, soonest=soonest, join_busy=False)
        _, steer_to = policy.plan(_view(k, s.starts, 10))
        first = 1 if soonest else 0
        assert [int(steer_to[r]) for r in pair] == [first, first]
        assert int(steer_to[alone]) != first


# -- news of a knower renews patience ----------------------------------------------------


def test_news_of_another_knower_renews_a_waiting_robots_patience():
    # r1 waits at t1 (needs 3), which r2 knows too; at step 30 r1 sees r3 find it. With
    # `rejoin` it waits 60 steps from then (gives up at 90), without it from step 0 (60);
    # it steers elsewhere from the next step. (`fetch_together` off: r2 and r3 never
    # seen, r1 would go with r2 to fetch r3 rather than wait.)
    s = CollaborativeScenario(
        [[10, 10, 0], [28, 28, 0], [2, 28, 0]], [[10, 10]], (3,),
        workspace=30.0, sensing_range=7.0,
    )  # fmt: skip
    gave_up = {}
    for rejoin in (True, False):
        k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((3, 1), dtype=bool))
        k.discover(0, np.array([True, True, False]))
        policy = _policy(s, rejoin=rejoin, stale_after=0, fetch_together=False)
        for step in range(120):
            if step == 30:
                k.discover(0, np.array([True, False, True]))
            unseen = np.full((3, 3), -1)
            np.fill_diagonal(unseen, step)
            view = _view(k, s.starts, step, open_seen=np.full((3, 1), step), last_seen=unseen)
            _, steer_to = policy.plan(view)
            if steer_to[0] != 0:
                gave_up[rejoin] = step
                break
    assert gave_up == {True: 91, False: 61}


# -- a lone knower looks for helpers, then waits ---------------------------------------------


def test_a_lone_knower_looks_for_helpers_for_a_while_then_waits_at_the_task():
    # r1 stands at t1 (needs 2), which only it knows from step 50 on; it has not seen r2
    # or r3 for more than 40 steps (`fetch_memory`), so it knows nobody to fetch. With
    # `seek_limit` 20 it explores (looks for helpers) at steps 50-69, waits at t1 from 70
    # until its patience (60) runs out at 130, explores on hold (40 steps) from 131 to
    # 169, and looks anew from 170: waits again from 190.
    # Without a limit it looks for helpers for good (three robots that each know a task
    # nobody else is known to know of, on parallel sweeps, may never meet).
    s = CollaborativeScenario(
        [[10, 10, 0], [28, 28, 0], [2, 28, 0]], [[10, 10]], (2,),
        workspace=30.0, sensing_range=7.0,
    )  # fmt: skip
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((3, 1), dtype=bool))
    k.discover(0, np.array([True, False, False]))
    unseen = np.full((3, 3), -1)
    for limit, waits in ((20, [*range(70, 131), *range(190, 200)]), (0, [])):
        policy = _policy(s, seek_limit=limit, stale_after=0)
        steer = []
        for step in range(50, 200):
            np.fill_diagonal(unseen, step)
            view = _view(k, s.starts, step, open_seen=np.full((3, 1), step), last_seen=unseen)
            steer.append(int(policy.plan(view)[1][0]))
        assert [50 + step for step, t in enumerate(steer) if t == 0] == waits
        assert set(steer) <= {0, -1}


# -- a fetcher turns back once the teammate will see it turn ---------------------------------


@pytest.mark.parametrize(("gap", "steer"), [(6.5, FETCHING), (5.5, FETCHING), (5.0, 0)])
def test_a_fetcher_heads_back_once_the_teammate_still_sees_it_after_a_step(gap, steer):
    # r1 alone knows t1 (needs 2) and fetches r2, in sight (7 m) `gap` m east. Both move
    # 1 m a step: turning back further than 7 - 2 = 5 m, r1 could be out of r2's sight by
    # the time the heading event fires (r2 turning away too, to fetch r1 for a task of its
    # own: two such fetchers dithered at the edge of sight for 40 steps). So it goes on
    # towards r2, and heads for the task from 5 m.
    s = CollaborativeScenario(
        [[20, 15, 0], [20 + gap, 15, 0]], [[3, 15]], (2,), workspace=30.0, sensing_range=7.0
    )
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 1), dtype=bool))
    k.discover(0, np.array([True, False]))
    targets, steer_to = _policy(s).plan(_view(k, s.starts, 50, open_seen=np.full((2, 1), 50)))
    assert int(steer_to[0]) == steer
    assert targets[0].tolist() == ([20 + gap, 15] if steer == FETCHING else [3, 15])


@pytest.mark.parametrize(
    ("horizon", "steer", "goes_to"), [(0, FETCHING, [15, 20]), (20, 0, [15, 5])]
)
def test_a_knower_waits_for_a_teammate_its_sweep_brings_within_the_horizon(horizon, steer, goes_to):
    # 30 m, 7 m of sight: r2 (second of two) sweeps the lane x = 15 downwards, 1 m a step,
    # and is at (15, 20) now. r1 alone knows t1 at (15, 5) (needs 2) and stands there. r2
    # comes within 0.8 * 7 = 5.6 m of t1 at y = 10.6, after 9.4 steps: within a horizon
    # of 20 steps r1 waits for it; with none it goes and fetches it where it is.
    s = CollaborativeScenario(
        [[15, 5, 0], [15, 20, 0]], [[15, 5]], (2,), workspace=30.0, sensing_range=7.0
    )
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 1), dtype=bool))
    k.discover(0, np.array([True, False]))
    policy = _policy(s, wait_horizon=horizon)
    targets, steer_to = policy.plan(_view(k, s.starts, 50, open_seen=np.full((2, 1), 50)))
    assert int(steer_to[0]) == steer
    assert targets[0].tolist() == goes_to


@pytest.mark.parametrize(
    ("together", "starts", "steer", "goes_to"),
    [
        (True, [[6, 15, 0], [12, 15, 0], [25, 15, 0]], FETCHING, [25, 15]),
        (False, [[6, 15, 0], [12, 15, 0], [25, 15, 0]], 0, [5, 15]),
        (True, [[6, 15, 0], [12, 15, 0], [25, 15, 0], [25, 17, 0]], 0, [5, 15]),
        (True, [[6, 15, 0], [12, 15, 0], [25, 15, 0], [28, 28, 0]], FETCHING, [25, 15]),
    ],
)
def test_the_nearest_knower_waits_only_if_someone_may_see_it_wait(together, starts, steer, goes_to):
    # r1 and r2 found t1 (5, 15), which needs 3, together: each knows the other knows.
    # r3, 20 m from t1 (out of 7 m sight of it), does not know; r2 fetches it. r1, the
    # knower nearest t1, waits there to be seen by a teammate that does not know, but
    # with three robots nobody is left to see it: it goes for r3 too. A fourth robot
    # that does not know may pass by if it is within `watch_range` (3) sensing ranges,
    # 21 m, of t1: at (25, 17), 20.1 m away, it may, and r1 waits; at (28, 28), 26.4 m
    # away, it is too far, and r1 goes for r3 too.
    s = CollaborativeScenario(starts, [[5, 15]], (3,), workspace=30.0, sensing_range=7.0)
    n = len(starts)
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((n, 1), dtype=bool))
    k.discover(0, np.arange(n) < 2)
    policy = _policy(s, fetch_together=together)
    view = _view(k, s.starts, 50, open_seen=np.full((n, 1), 50))
    assert view.aware[0, 1, 0] and view.aware[1, 0, 0] and not view.aware[0, 2, 0]
    targets, steer_to = policy.plan(view)
    assert int(steer_to[0]) == steer
    assert targets[0].tolist() == goes_to
    assert int(steer_to[1]) == FETCHING and targets[1].tolist() == [25, 15]


# -- a teammate known to be on its sweep -------------------------------------------------


def test_a_teammate_is_known_on_its_sweep_until_it_could_have_found_a_task():
    # 30 m, 7 m of sight, lanes 14 m apart at most: x = 5, 15, 25, from y = 5 to 25. r2
    # (second of two) starts on the middle lane going down: (15, 25) -> (15, 5). r1 saw it
    # there at step 0; at step 12 r2 has swept (15, 25) -> (15, 13).
    s = CollaborativeScenario(
        [[2, 2, 0], [15, 25, 0]], [[25, 25], [20, 15]], (2, 2),
        workspace=30.0, sensing_range=7.0,
    )  # fmt: skip
    policy = _policy(s)
    assert policy.routes[1].points[:2].tolist() == [[15.0, 25.0], [15.0, 5.0]]
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 2), dtype=bool))
    k.discover(0, np.array([True, False]))  # r1 alone knows t1
    last_seen = np.array([[12, 0], [0, 12]])
    view = _view(k, s.starts, 12, last_seen=last_seen)
    # t1 is 10 m from the nearest point r2 swept, (15, 25): r2 cannot have found it
    assert policy.on_sweep(view, 0, 1, np.array([True, False])) is True
    # t2 is 5 m from (15, 15), which r2 passed: it found t2, and went there
    assert policy.on_sweep(view, 0, 1, np.array([True, True])) is False
    # r1 knows r2 knows of t1: r2 may be going there
    k.discover(0, np.array([True, True]))
    view = _view(k, s.starts, 12, last_seen=last_seen)
    assert policy.on_sweep(view, 0, 1, np.array([True, False])) is False


# -- the world: a task done is not found again ---------------------------------------------


@pytest.mark.parametrize("level", ["rules-first", "rules"])
def test_no_task_is_found_after_it_is_done(level):
    mission = load_mission("specs/collaborative/tasks_5.epi")
    for seed in range(4):
        trial = simulate(mission.scenario(seed), level, seed, parameters=mission.parameters)
        done = {mission.scenario(seed).task_names[t]: d for t, d in enumerate(trial.tasks_done)}
        for step, name, args, _ in trial.events:
            if name == "found":
                assert done[args[1]] < 0 or step < done[args[1]]


# -- the firing loop the simulators share -------------------------------------------------


def _one_task_world(task_open: bool) -> World:
    """r1 steps to within 7 m of t1 (from 8 m) and reaches it; r2, 3 m away, sees r1, r3
    (20 m away) does not."""
    now = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [20.0, 0.0, 0.0]])
    before = now + np.array([[0.0, -8.0, 0.0], [0, 0, 0], [0, 0, 0]])
    visible = np.hypot(*(now[:, None, :2] - now[None, :, :2]).transpose(2, 0, 1)) <= 7.0
    flags = np.full(1, task_open)
    return World(1, now, before, np.array([[0.0, 0.0]]), flags, flags, visible, 7.0, 1.5,
                 ("range",) * 3, ("r1", "r2", "r3"), ("t1",))  # fmt: skip


def test_firings_split_arrivals_from_perception_and_name_the_observers():
    rules = load_mission("specs/collaborative/tasks_3.epi").parts.events
    world = _one_task_world(task_open=True)
    seen = [(rule.name, f.binding) for rule, f in firings(rules, world, arrivals=False)]
    assert seen == [("found", {"r": "r1", "t": "t1"})]  # r2 was within 7 m already
    done = firings(rules, world, arrivals=True)
    assert [rule.name for rule, _ in done] == ["done"]
    assert observer_indices(done[0][1].observation, world.robots) == (0, 1)


def test_a_closed_goal_is_not_discovered_by_either_simulator():
    # The world of the test above with t1 closed (done): r1 comes within 7 m of it but
    # finds nothing; the rule lives in the firing loop, so the generic simulator has it too
    rules = load_mission("specs/collaborative/tasks_3.epi").parts.events
    assert firings(rules, _one_task_world(task_open=False), arrivals=False) == []
