"""The collaborative planning levels (sim/policies/collaborative_planning.py): registered
beside the rules, deciding by what the robot knows its teammates know, and closed loop."""

import numpy as np
import pytest

from epistemica import InvalidArgumentError
from epistemica.generate import mission_text
from epistemica.mission import parse_mission
from epistemica.sim import simulate
from epistemica.sim.engine.joint import JointView
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.policies.collaborative_levels import FETCHING
from epistemica.sim.policies.collaborative_planning import (
    PLANNING_LEVELS,
    CollaborativeParameters,
    PlanningCollaborativePolicy,
    explain,
)
from epistemica.sim.policies.levels import JOINT_LEVELS, level_names, make_level


def test_the_planning_levels_sit_beside_the_rules():
    names = level_names("collaborative")
    assert names[: len(names) - len(PLANNING_LEVELS)][-1] == "convention+rules"
    assert set(PLANNING_LEVELS) <= set(names)
    assert make_level("collaborative", "third").order == 3
    assert make_level("collaborative", "third-priormode").order == 0
    assert make_level("collaborative", "rules").style == "third"
    assert all(JOINT_LEVELS[name].description for name in PLANNING_LEVELS)


def _view(step, poses, knowledge):
    """Everyone sees everyone at ``step``; the ledger read from ``knowledge``."""
    n, m = len(poses), knowledge.m
    pairs = [[(i,) if i == j else (i, j) for j in range(n)] for i in range(n)]
    aware = np.array([[knowledge.knows_goals(chain) for chain in row] for row in pairs])
    estimates = np.broadcast_to(poses[None, :, :2], (n, n, 2)).copy()
    seen = np.full((n, n), step)
    return JointView(step, poses, estimates, seen, knowledge, aware,
                     np.where(aware, 0, -1), np.full((n, m), step))  # fmt: skip


def _scene(together: bool):
    """r1 at (20, 15) found t1 at (3, 15), which needs 2; r2 stands 6.5 m off, in sight,
    and saw it found if ``together``. The scenario, and the view at step 50."""
    s = CollaborativeScenario([[20, 15, 0], [26.5, 15, 0]], [[3, 15]], (2,), workspace=30.0,
                              sensing_range=7.0)  # fmt: skip
    knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 1), dtype=bool))
    knowledge.discover(0, np.array([True, together]))
    return s, _view(50, np.asarray(s.starts, dtype=float), knowledge)


@pytest.mark.parametrize("together", [False, True])
def test_a_teammate_is_fetched_only_when_it_is_known_not_to_know(together):
    # r1 at (20, 15) found t1 at (3, 15), which needs 2; r2 stands 6.5 m off, in sight.
    # If r2 saw it found, r1 knows r2 knows: both go. If not, r1 fetches r2 at third;
    # third-shared takes r2 to know and heads for the task.
    s, view = _scene(together)
    steer = {}
    for level in ("third", "third-shared"):
        policy = make_level("collaborative", level)
        policy.start(s)
        steer[level] = int(policy.plan(view)[1][0])
    assert steer["third-shared"] == 0
    assert steer["third"] == (0 if together else FETCHING)


@pytest.mark.parametrize("retry", [False, True])
def test_a_teammate_given_up_on_is_fetched_again_once_seen_with_plan_retry(retry):
    # The scene above, r2 not knowing of t1; r1 had given up fetching it (it was not
    # where its sweep put it). r2 is in sight now: with plan_retry r1 fetches it again.
    s, view = _scene(together=False)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_retry=retry))
    policy.start(s)
    policy.gave_up[0, 0, 1] = True
    steer = int(policy.plan(view)[1][0])
    assert (steer == FETCHING) == retry
    assert policy.gave_up[0, 0, 1] == (not retry)


@pytest.mark.parametrize("rollout", [0.0, 6.0])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_small_mission_succeeds_at_third(seed, rollout):
    # seed 2 with plan_rollout once chased teammates out fetching to the step limit
    s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=seed)
    parameters = CollaborativeParameters(plan_rollout=rollout)
    trial = simulate(s, PlanningCollaborativePolicy("third", parameters), seed=seed,
                     parameters=parameters)  # fmt: skip
    assert trial.success
    assert (trial.tasks_done >= 0).all() and trial.completion_step == trial.tasks_done.max()


def test_a_traced_trial_is_the_same_trial_with_every_decision_kept():
    s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=2)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(), trace=True)
    traced = simulate(s, policy, seed=2)
    plain = simulate(s, "third", seed=2)
    assert (traced.success, traced.steps) == (plain.success, plain.steps)
    np.testing.assert_array_equal(traced.trajectory, plain.trajectory)
    assert [(d.step, d.robot) for d in policy.trace] == [
        (step, robot) for step in range(traced.steps) for robot in range(3)
    ]
    for d in policy.trace:
        assert np.isfinite(d.G[d.choice]) and d.G[d.choice] <= d.G.min() + 1e-9
        kind = d.options[d.choice][0]
        steer = traced.steer_to[d.step, d.robot]
        if kind == "explore":
            assert steer in (-1, *range(len(s.needs)))  # exploring, or verifying a task
        elif kind == "task":
            assert steer == d.options[d.choice][1]
    assert "| yes |" in explain(policy.trace[-1])


def test_a_fetch_meets_the_helper_where_it_is_then_both_go_at_the_slower_speed():
    s, view = _scene(together=False)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_fetchers=True))
    policy.start(s)
    policy.plan(view)
    policy.arrivals(view, 0)
    speed = np.asarray(s.max_speed, dtype=float) * s.dt
    r1, r2, t1 = np.asarray(s.starts, dtype=float)[0, :2], np.asarray(s.starts)[1, :2], s.tasks[0]
    want = np.linalg.norm(r2 - r1) / speed[0] + np.linalg.norm(t1 - r2) / speed.min()
    assert policy.meetings()[0, 1, 0] == pytest.approx(want)
    assert policy.meetings()[1, 1, 0] == pytest.approx(np.linalg.norm(t1 - r2) / speed[1])


@pytest.mark.parametrize("seed", [1, 2])
def test_a_small_mission_succeeds_with_teammates_fetches_predicted(seed):
    s = CollaborativeScenario.drawn(robots=4, needs=(3, 2), seed=seed)
    parameters = CollaborativeParameters(plan_fetchers=True)
    assert simulate(s, "third", seed=seed, parameters=parameters).success


class _Recording(PlanningCollaborativePolicy):
    """Keeps the geometry each plan was given, and where the policy predicted robots."""

    def start(self, scenario, robots=None, generators=None) -> None:
        super().start(scenario, robots, generators)
        self.given, plan = [], self.planner.plan

        def recorded(*args, **kwargs):
            self.given.append((args[-1], self.where.copy()))
            return plan(*args, **kwargs)

        self.planner.plan = recorded


@pytest.mark.parametrize("horizon", [0.0, 6.0])
def test_plan_rollout_gives_the_planner_its_horizon_and_the_predicted_geometry(horizon):
    s = CollaborativeScenario.drawn(robots=4, needs=(3, 2), seed=1)
    parameters = CollaborativeParameters(plan_rollout=horizon)
    policy = _Recording("third", parameters)
    assert simulate(s, policy, seed=1, parameters=parameters).success
    crossing = s.workspace / (np.mean(s.max_speed) * s.dt)
    assert policy.planner.rollout == pytest.approx(horizon * crossing)
    for geometry, where in policy.given:
        if horizon == 0:
            assert geometry is None
            continue
        assert np.array_equal(geometry.positions, where)
        assert np.allclose(geometry.speed, np.asarray(s.max_speed) * s.dt)
        assert np.array_equal(geometry.tasks, s.tasks)


@pytest.mark.parametrize("rollout", [0.0, 6.0])
@pytest.mark.parametrize("x", [4.0, 6.5, 26.5])
def test_with_plan_rollout_a_teammate_seen_standing_at_a_task_is_taken_to_know_of_it(x, rollout):
    # r1 at (20, 15) knows of t1 at (3, 15); r2 at (x, 15), in sight, never saw t1 found.
    # Within two completion radii of t1 (1.5 m each) it stands there: r1 counts it a knower.
    s = CollaborativeScenario([[20, 15, 0], [x, 15, 0]], [[3, 15]], (2,), workspace=30.0,
                              sensing_range=30.0)  # fmt: skip
    knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 1), dtype=bool))
    knowledge.discover(0, np.array([True, False]))
    view = _view(50, np.asarray(s.starts, dtype=float), knowledge)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_rollout=rollout))
    policy.start(s)
    sets, _ = policy.chains(view, 0, np.zeros(1, dtype=bool))
    standing = abs(x - 3.0) <= 2 * s.completion_radius
    assert sets[(0,)].tolist() == [True]
    assert sets[(0, 1)].tolist() == [bool(rollout) and standing]


@pytest.mark.parametrize("rollout", [0.0, 6.0])
@pytest.mark.parametrize("off", [False, True])
def test_with_plan_rollout_a_teammate_seen_off_its_sweep_is_not_intercepted(off, rollout):
    # The scene above, r2 not knowing of t1, placed on its sweep or as far off it as the
    # workspace allows. Seen off it, it is busy elsewhere (a task r1 does not know of, or a
    # fetch): with plan_rollout r1 does not offer to intercept it on its sweep.
    s, view = _scene(together=False)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_rollout=rollout))
    policy.start(s)
    route = policy.routes[1]
    grid = np.stack(np.meshgrid(np.linspace(1, 29, 29), np.linspace(1, 29, 29)), -1).reshape(-1, 2)
    place = grid[np.argmax([route.gap(q) for q in grid])] if off else route.points[0]
    assert (route.gap(place) > policy.parameters.off_sweep * s.sensing_range) == off
    view.poses[1, :2] = place
    view.estimates[:, 1] = place
    policy.plan(view)
    offered = [(f.task, f.helper) for f in policy.fetches(view, 0)]
    assert policy.meet(view, 0, 1) is not None  # the intercept itself is there either way
    assert offered == ([] if off and rollout else [(0, 1)])


def _sighted_scene(x: float, step: int = 50):
    """r1 at (12, 15) found t1 at (3, 15), which needs 2, alone; r2 at (x, 15), seen by r1,
    never seen at the task's finding (the ledger has r1 alone knowing of it). Sight 10 m."""
    s = CollaborativeScenario([[12, 15, 0], [x, 15, 0]], [[3, 15]], (2,), workspace=30.0,
                              sensing_range=10.0)  # fmt: skip
    knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 1), dtype=bool))
    knowledge.discover(0, np.array([True, False]))
    return s, _view(step, np.asarray(s.starts, dtype=float), knowledge)


@pytest.mark.parametrize("sighted", [False, True])
@pytest.mark.parametrize("x", [10.0, 13.0, 14.0])
def test_with_plan_sighted_a_teammate_seen_with_a_task_in_sight_knows_of_it(x, sighted):
    # r2 is |x - 3| m from t1: 7 and 10 are within the 10 m of sight (it sees t1, so it
    # knows of it, though no shared event says so), 11 is not. With plan_sighted r1 counts
    # it a knower and does not offer to fetch it for t1.
    s, view = _sighted_scene(x)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_sighted=sighted))
    policy.start(s)
    policy.plan(view)
    knows = sighted and abs(x - 3.0) <= 10.0
    assert view.aware[0, 1].tolist() == [False]
    sets, unknown = policy.chains(view, 0, np.zeros(1, dtype=bool))
    assert sets[(0, 1)].tolist() == [knows]
    assert unknown[(0, 1)] == (0 if knows else 1)
    offered = [(f.task, f.helper) for f in policy.fetches(view, 0)]
    assert offered == ([] if knows else [(0, 1)])


def test_with_plan_sighted_what_a_teammate_was_seen_to_see_is_remembered():
    # r1 sees r2 7 m from t1 at step 50; at step 51 r2 is 15 m from it, still in sight:
    # it saw t1 a step ago, so it still knows of it. Seen at 15 m only, it would not.
    s, view = _sighted_scene(10.0)
    far = np.array([[12.0, 15.0, 0.0], [18.0, 15.0, 0.0]])
    estimates = np.broadcast_to(far[None, :, :2], (2, 2, 2)).copy()
    later = view._replace(step=51, poses=far, estimates=estimates, last_seen=np.full((2, 2), 51))
    fresh = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_sighted=True))
    fresh.start(s)
    fresh.plan(later)
    assert fresh.chains(later, 0, np.zeros(1, dtype=bool))[0][(0, 1)].tolist() == [False]
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_sighted=True))
    policy.start(s)
    policy.plan(view)
    policy.plan(later)
    assert policy.chains(later, 0, np.zeros(1, dtype=bool))[0][(0, 1)].tolist() == [True]
    assert policy.seen[:, :, 0].tolist() == [[True, True], [True, True]]


def _events(seed: int) -> tuple:
    """The observation events of generated collaborative mission ``seed``."""
    return parse_mission(mission_text("collaborative", seed), "m.epi").scenario(0).events


@pytest.mark.parametrize("hail", [False, True])
@pytest.mark.parametrize("seed", [123, 175])
def test_with_plan_hail_a_teammate_is_fetched_only_where_a_hail_tells_it(seed, hail):
    # The scene of the fetch above (r2 does not know of t1), with the events of generated
    # mission 123 (found, heading, done: a teammate that sees r1 head for t1 learns of it)
    # or 175 (found, done: nothing r1 does on the way tells r2 of t1). With plan_hail r1
    # offers to fetch r2 only where the heading event exists (plan_told off: it would drop
    # the fetch of mission 175 too, r2 not being in sight where r1 finds t1 again).
    s, view = _scene(together=False)
    s = s.replace(events=_events(seed))
    parameters = CollaborativeParameters(plan_hail=hail, plan_told=False)
    policy = PlanningCollaborativePolicy("third", parameters)
    policy.start(s)
    policy.plan(view)
    heading = any(e.name == "heading" for e in s.events)
    assert heading == (seed == 123)
    offered = [(f.task, f.helper) for f in policy.fetches(view, 0)]
    assert offered == ([(0, 1)] if heading or not hail else [])


def _two_tasks():
    """r1 at (20, 15) found t1 at (3, 15) and t2 at (20, 3), alone; r2 6.5 m off, in sight."""
    s = CollaborativeScenario([[20, 15, 0], [26.5, 15, 0]], [[3, 15], [20, 3]], (2, 2),
                              workspace=30.0, sensing_range=7.0)  # fmt: skip
    knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 2), dtype=bool))
    knowledge.discover(0, np.array([True, False]))
    knowledge.discover(1, np.array([True, False]))
    return s, _view(50, np.asarray(s.starts, dtype=float), knowledge)


@pytest.mark.parametrize("lost", [False, True])
def test_with_plan_lost_a_teammate_given_up_for_one_task_is_not_fetched_for_another(lost):
    # r1 gave up fetching r2 for t1 (r2 was not where its sweep put it): with plan_lost it
    # does not offer to fetch r2 for t2 either; without, only the fetch for t1 is gone.
    s, view = _two_tasks()
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_lost=lost))
    policy.start(s)
    policy.plan(view)
    assert [(f.task, f.helper) for f in policy.fetches(view, 0)] == [(0, 1), (1, 1)]
    policy.gave_up[0, 0, 1] = True
    offered = [(f.task, f.helper) for f in policy.fetches(view, 0)]
    assert offered == ([] if lost else [(1, 1)])


@pytest.mark.parametrize("alive", [0, 1])
@pytest.mark.parametrize("lost", [False, True])
def test_with_plan_lost_a_never_seen_teammate_with_no_start_left_is_not_fetched(lost, alive):
    # r2 never seen by r1; every start of its grid but ``alive`` of them ruled out (it
    # would have been seen): with none left it left its sweep, and plan_lost offers no
    # intercept of it on its sweep.
    s, view = _two_tasks()
    view.last_seen[0, 1] = -1
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_lost=lost))
    policy.start(s)
    policy.plan(view)
    policy.teammates.alive[0, 1] = False
    policy.teammates.alive[0, 1, :alive] = True
    assert policy.lost(view, 0, 1) == (alive == 0)
    offered = [f.helper for f in policy.fetches(view, 0)]
    assert offered == ([] if lost and alive == 0 else [1, 1])


def _hail(**options):
    """The two-task scene with no heading event (generated mission 175: found, done) and r2
    3 m from r1, in sight, within hailing distance (sight less both robots' step): the
    scenario, the view before r2 moved, and the step's targets and steering of a policy
    with ``options`` (plan_told off: it is tested below) that planned there."""
    s, view = _two_tasks()
    s = s.replace(events=_events(175))
    poses = view.poses.copy()
    poses[1, 0] = 23.0
    near = view._replace(poses=poses, estimates=np.broadcast_to(poses[None, :, :2], (2, 2, 2)))
    speed = np.asarray(s.max_speed, dtype=float) * s.dt
    assert 3.0 <= s.sensing_range - speed.sum()
    policy = PlanningCollaborativePolicy(
        "third", CollaborativeParameters(plan_told=False, **options)
    )
    policy.start(s)
    return s, view, policy, *policy.plan(near)


@pytest.mark.parametrize("hailed", [False, True])
def test_with_plan_hailed_a_teammate_hailed_for_a_task_is_not_fetched_for_it_again(hailed):
    # r1 knows t1 and t2 alone; r2 is within hailing distance (_hail). r1 fetches r2, so it
    # turns for the task at once: the hail. Nothing tells r2 of it, so the ledger still
    # has r2 unaware; with plan_hailed r1 no longer offers that fetch (the other task's
    # still stands), and seeing r2 again does not lift it.
    s, view, policy, targets, steer_to = _hail(plan_hailed=hailed)
    kind, task, helper = policy.previous[0]
    assert (kind, helper) == ("fetch", 1) and steer_to[0] == task
    assert targets[0].tolist() == s.tasks[task].tolist()
    assert policy.hailed[0, :, 1].tolist() == [50 if t == task else -1 for t in range(2)]
    later = view._replace(step=51, last_seen=np.full((2, 2), 51))
    offered = [(f.task, f.helper) for f in policy.fetches(later, 0)]
    assert offered == [(t, 1) for t in range(2) if not (hailed and t == task)]


@pytest.mark.parametrize("chase", [0, 40])
def test_with_plan_chase_a_teammate_hailed_that_long_ago_is_not_fetched_for_that_task(chase):
    # The hail above at step 50 (no heading event, so it told r2 nothing). With plan_chase
    # 40, r1 still offers that fetch at steps 51 and 89 (r2 may yet see it find the task)
    # and no longer from step 90, 40 steps after the first hail, though r2 is in sight; the
    # other task's fetch stands. A second hail does not move the first hail's step.
    _, view, policy, _, steer_to = _hail(plan_chase=chase)
    kind, task, helper = policy.previous[0]
    assert (kind, helper) == ("fetch", 1) and steer_to[0] == task and policy.silent
    for step, banned in ((51, False), (89, False), (90, True), (200, True)):
        later = view._replace(step=step, last_seen=np.full((2, 2), step))
        offered = [(f.task, f.helper) for f in policy.fetches(later, 0)]
        assert offered == [(t, 1) for t in range(2) if not (chase and banned and t == task)]
    policy.plan(view._replace(step=60, last_seen=np.full((2, 2), 60)))
    assert policy.hailed[0, task, 1] == 50


@pytest.mark.parametrize("back", [False, True])
def test_with_plan_back_a_fetcher_that_hailed_goes_on_to_the_task(back):
    # The hail of the test above (no heading event): r1, 3 m from r2, turns for the task.
    # A step later r2 is 6.5 m off, out of hailing distance (7 m less both robots' step);
    # r1 still fetches r2 for that task. Without plan_back it turns for r2 again (the chase
    # of found-only missions); with it, it goes on to the task, where r2 may see it.
    s, view, policy, _, steer_to = _hail(plan_back=back)
    hail = policy.previous[0]
    assert hail[0] == "fetch" and steer_to[0] == hail[1] and policy.back[0] == hail
    later = view._replace(step=51, last_seen=np.full((2, 2), 51))
    targets, steer_to = policy.plan(later)
    assert policy.previous[0] == hail
    assert steer_to[0] == (hail[1] if back else FETCHING)
    if back:
        assert targets[0].tolist() == s.tasks[hail[1]].tolist()
    assert policy._leg(0, ("explore",)) == ("explore",) and policy.back[0] is None


@pytest.mark.parametrize("waiting", [False, True])
def test_plan_told_a_fetch_tells_a_task_only_where_the_helper_sees_it_found_or_waited_at(waiting):
    # No heading event (generated mission 201: found within 5 m, waiting, done; without
    # waiting, found-only): r2 (held at (26.5, 15), sight 7 m) learns of a task only if it
    # sees r1, met at r2's place, re-enter 5 m of the task on the way back, or (waiting)
    # stand at it. Task (26.5, 3.5): re-entered at (26.5, 8.5), 6.5 m off, seen; (26.5, 2):
    # at (26.5, 7), 8 m, not; (26.5, 10): within 5 m at the meeting (no re-entry), stood at
    # 5 m off: seen only where waiting tells.
    s = CollaborativeScenario([[20, 15, 0], [26.5, 15, 0]], [[26.5, 3.5], [26.5, 2], [26.5, 10]],
                              (2, 2, 2), workspace=30.0, sensing_range=7.0)  # fmt: skip
    s = s.replace(events=tuple(e for e in _events(201) if waiting or e.name != "waiting"))
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_told=True))
    policy.start(s)
    policy.predicted = lambda view, i, j, ahead=0: np.array([26.5, 15.0])
    assert (policy.hails, policy.reach, policy.settle) == (False, 5.0, waiting)
    told = policy.told(None, 0, 1, (4.0, (26.5, 15.0)))
    assert told.tolist() == [True, False, waiting]


@pytest.mark.parametrize("insight", [False, True])
def test_with_plan_insight_a_teammate_in_sight_is_met_where_it_is_seen(insight):
    # r2, 6.5 m from r1 and in sight, is met where r1 sees it once r1 is at hailing
    # distance (sight less both robots' step), not on its sweep; then both go 23.5 m to t1.
    s, view = _scene(together=False)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_insight=insight))
    policy.start(s)
    policy.plan(view)
    (fetch,) = policy.fetches(view, 0)
    speed = np.asarray(s.max_speed, dtype=float) * s.dt
    hail = s.sensing_range - speed.sum()
    swept = policy.meet(view, 0, 1)
    when, where = ((6.5 - hail) / speed[0], (26.5, 15.0)) if insight else swept
    assert fetch.meeting == pytest.approx(when)
    assert fetch.place == pytest.approx(tuple(where))
    back = np.hypot(*(np.asarray(where) - s.tasks[0]))
    assert fetch.arrival == pytest.approx(when + back / speed[0])
    assert (fetch.place == pytest.approx((26.5, 15.0))) == insight


@pytest.mark.parametrize("hold", [False, True])
def test_with_plan_hold_a_task_waited_at_in_vain_is_no_option_while_on_hold(hold):
    # Both robots know of t1 (needs 2): r1 goes there. Had r1 waited there in vain until
    # step 45 (on hold until 85, when the ledger had the same two knowers), with plan_hold
    # going there is no option at step 50, as for the rules.
    s, view = _scene(together=True)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_hold=hold))
    policy.start(s)
    policy.hold_until[0, 0], policy.held_knowers[0, 0] = 85, 2
    assert policy.unheld(view, 0, np.zeros(1), view.aware).tolist() == [False]
    steer = int(policy.plan(view)[1][0])
    assert (steer == 0) == (not hold)
    policy.held_knowers[0, 0] = 1  # one more knower since: it may try again
    assert int(policy.plan(view)[1][0]) == 0


def test_spread_is_the_share_of_a_never_seen_teammates_starts_in_sight_of_a_place():
    # A 30 m workspace, sight 7 m, a 2 x 2 grid of starts: (7.5, 7.5), (22.5, 7.5),
    # (7.5, 22.5), (22.5, 22.5). At step 0 r2 is still at its start. From (12, 12) only
    # (7.5, 7.5) is in sight (6.4 m; (22.5, 7.5) is 11.4 m off); from (15, 15) none (10.6
    # m each); from (15, 7.5) none (7.5 m both ways); from (16, 7.5) only (22.5, 7.5)
    # (6.5 m, and 8.5 m to (7.5, 7.5)). With (7.5, 7.5) ruled out, none of the three
    # left is in sight of (12, 12); with every start ruled out, the plain guess: 1.
    s = CollaborativeScenario([[20, 15, 0], [26.5, 15, 0]], [[3, 15]], (2,), workspace=30.0,
                              sensing_range=7.0)  # fmt: skip
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(particles=2))
    policy.start(s)
    places = [(12, 12), (15, 15), (15, 7.5), (16, 7.5)]
    assert [policy.teammates.spread(0, 0, 1, p) for p in places] == [0.25, 0.0, 0.0, 0.25]
    policy.teammates.alive[0, 1, 0] = False
    assert policy.teammates.spread(0, 0, 1, (12.0, 12.0)) == 0.0
    policy.teammates.alive[0, 1] = False
    assert policy.teammates.spread(0, 0, 1, (12.0, 12.0)) == 1.0


@pytest.mark.parametrize("spread", [False, True])
def test_with_plan_spread_a_never_seen_teammate_is_found_as_often_as_its_starts_allow(spread):
    # The two-task scene at step 50, r2 never seen by r1 (fetch_memory 40: found
    # exp(-50 / 40) = 0.287 on its sweep). Leave two starts of the grid: the intercept
    # aims at the median of their arcs, and with plan_spread found is 0.287 times the
    # share of their two places in sight of the meeting (0, 1/2 or 1); off, 0.287.
    s, view = _two_tasks()
    view.last_seen[0, 1] = -1
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_spread=spread))
    policy.start(s)
    policy.plan(view)
    grid, left = policy.teammates.alive.shape[-1], np.flatnonzero(policy.teammates.alive[0, 1])
    shares = set()
    for k in left[1:]:
        policy.teammates.alive[0, 1] = np.isin(np.arange(grid), [left[0], k])
        fetch = policy.fetches(view, 0)[0]
        there = policy.teammates.possible(view.step + fetch.meeting, 0, 1)
        share = np.mean(np.hypot(*(there - np.asarray(fetch.place)).T) <= s.sensing_range)
        assert fetch.found == pytest.approx(np.exp(-50 / 40) * (share if spread else 1.0))
        shares.add(float(share))
    assert len(shares) > 1  # the share differs across the grid


def _watched_case():
    """Task t1 at (3, 15) needs 2; r2 and r3 at (20, 16) and (21, 14) have been known to
    know of it since step 0; the view is r1's at step 50."""
    s = CollaborativeScenario([[20, 15, 0], [20, 16, 0], [21, 14, 0]], [[3, 15]], (2,),
                              workspace=30.0, sensing_range=7.0)  # fmt: skip
    knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((3, 1), dtype=bool))
    knowledge.discover(0, np.array([True, True, True]))
    return s, _view(50, np.asarray(s.starts, dtype=float), knowledge)


@pytest.mark.parametrize("watched", [False, True])
@pytest.mark.parametrize("seen", [50, 10])
def test_with_plan_watched_a_knower_seen_away_counts_from_when_it_can_have_reached_the_task(
    watched, seen
):
    # Task t1 at (3, 15) needs 2; r2 and r3 have been known to know of it since step 0,
    # r1 last saw it open at step 0, step 50, stale_after 20: both knowers count and r1
    # presumes it done. With plan_watched, r2 and r3 were seen at (20, 16) and (21, 14) at
    # step ``seen``, 17.03 and 18.03 m off (speed 1 m a step, completion radius 1.5):
    # seen now, they can reach it at 65.5 and 66.5, too late to count; seen at step 10,
    # at 25.5 and 26.5 <= 30, they count.
    s, view = _watched_case()
    view = view._replace(last_seen=np.full((3, 3), seen), open_seen=np.zeros((3, 1), int))
    parameters = CollaborativeParameters(plan_watched=watched)
    policy = PlanningCollaborativePolicy("third", parameters)
    policy.start(s)
    gap = np.hypot(*(s.starts[1:, :2] - s.tasks[0]).T) - s.completion_radius
    assert policy.earliest(view, 0)[1:, 0] == pytest.approx(seen + gap)
    assert policy.presumed_done(view, 0, watched).tolist() == [not watched or seen == 10]


@pytest.mark.parametrize(("began", "presumed"), [(10, False), (16, False), (17, True), (50, True)])
def test_with_plan_watched_2_a_knower_seen_away_counts_if_it_can_have_been_there_first(
    began, presumed
):
    # As above (t1 at (3, 15) needs 2, r2 and r3 known to know of it since step 0, step
    # 50, stale_after 20), r2 and r3 seen at (20, 16) and (21, 14) without a break since
    # step ``began``: 15.53 and 16.53 steps from t1's radius. At 1 (plan_watched 1) both
    # count from 65.5 and 66.5 > 30, whenever the sighting began. At 2 a knower counts
    # from when r1 knew it knew (0 <= 30) if it had time to do t1 before the sighting
    # began and walk to where it was seen (began - walk >= 0): r2 from step 16, r3 from
    # 17; so t1 is presumed done from began 17 on (at 16 only r2 counts: 1 < 2).
    s, view = _watched_case()
    view = view._replace(open_seen=np.zeros((3, 1), int))
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_watched=2))
    policy.start(s)
    policy.watch(view._replace(step=began, last_seen=np.full((3, 3), began)))
    policy.watch(view)  # the same unbroken sighting
    assert policy.watch_from[0, 1:].tolist() == [began, began]
    assert policy.presumed_done(view, 0, 1).tolist() == [False]
    assert policy.presumed_done(view, 0, 2).tolist() == [presumed]
    assert policy.presumed_done(view, 0, 0).tolist() == [True]


def _waiter(moved: float):
    """r1 at (20, 15) knows t1 at (3, 15) and t2 at (20, 3), each needing 2; r2 stands 1 m
    off t2 at (20, 4) at steps 49 and 50 (moved ``moved`` m in between), knowing neither
    by the ledger. The scenario and the views of both steps."""
    s = CollaborativeScenario([[20, 15, 0], [20, 4 - moved, 0]], [[3, 15], [20, 3]], (2, 2),
                              workspace=30.0, sensing_range=7.0)  # fmt: skip
    knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 2), dtype=bool))
    knowledge.discover(0, np.array([True, False]))
    knowledge.discover(1, np.array([True, False]))
    before = _view(49, np.asarray(s.starts, dtype=float), knowledge)
    poses = np.array([[20.0, 15.0, 0.0], [20.0, 4.0, 0.0]])
    return s, before, _view(50, poses, knowledge)


@pytest.mark.parametrize("waiters", [0, 1, 2])
@pytest.mark.parametrize("moved", [0.0, 0.5])
def test_with_plan_waiters_a_teammate_standing_at_a_task_waits_there(waiters, moved):
    # With plan_waiters, r2, seen standing still at t2 (within two completion radii, 3 m;
    # moved less than 0.3 m a step), waits there: r1 takes it to know of t2 (no fetch for
    # t2) and meets it where it stands, 11 m off, once within hailing distance, 7 - 2 = 5
    # m: 6 steps; the trip to t1 is then 17^2 + 11^2 = 410, 20.25 m. Moving 0.5 m a step
    # it is not waiting, and without plan_waiters nobody is: the intercept on r2's sweep.
    # Only plan_waiters 1 hands the waiter to the planner to be predicted at its task.
    s, before, view = _waiter(moved)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_waiters=waiters))
    policy.start(s)
    policy.plan(before)
    policy.plan(view)
    waits = waiters > 0 and moved == 0.0
    policy.waiting_now = policy.waiters(view, 0)  # r1's decision, as choose sets it
    assert policy.waiting_now == ({1: 1} if waits else {})
    assert policy.staying() == ({1: 1} if waits and waiters == 1 else {})
    fetches = policy.fetches(view, 0)
    assert [(f.task, f.helper) for f in fetches] == ([(0, 1)] if waits else [(0, 1), (1, 1)])
    if waits:
        assert fetches[0].meeting == pytest.approx(6.0)
        assert fetches[0].place == (20.0, 4.0)
        assert fetches[0].arrival == pytest.approx(6.0 + np.sqrt(410.0))
    else:
        assert fetches[0].place != (20.0, 4.0)


def test_plan_waiters_is_0_1_or_2():
    with pytest.raises(InvalidArgumentError, match="plan_waiters"):
        CollaborativeParameters(plan_waiters=3)


@pytest.mark.parametrize("standing", [True, False])
def test_with_plan_presumed_a_teammate_away_from_a_task_found_open_presumes_it_done(standing):
    # r1 presumed t1 (index 0) done and found it open (doubted). r2, which the ledger says
    # knows of t1, is then taken to presume it done, for r1 does not see it stand there:
    # t1 leaves what r2 knows, and r1 may fetch it for t1 (as for t2, which r2 does not
    # know of). Doubting t2 instead, where r2 stands, changes nothing: r2 is fetched for
    # t2 alone.
    s, before, view = _waiter(0.0)
    knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((2, 2), dtype=bool))
    knowledge.discover(0, np.array([True, True]))  # both know of t1, only r1 of t2
    knowledge.discover(1, np.array([True, False]))
    before, view = _view(49, before.poses, knowledge), _view(50, view.poses, knowledge)
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_presumed=True))
    policy.start(s)
    policy.plan(before)
    policy.plan(view)
    policy.doubted[0] = [True, False] if not standing else [False, True]
    assert policy.presuming(view, 0).tolist() == (
        [[False, False], [False, False]] if standing else [[False, False], [True, False]]
    )
    knows = policy.knows(view, 0)
    assert knows[1, 0] == standing
    helpers = [(f.task, f.helper) for f in policy.fetches(view, 0)]
    assert helpers == ([(1, 1)] if standing else [(0, 1), (1, 1)])


def test_plan_presumed_is_0_or_1():
    with pytest.raises(InvalidArgumentError, match="plan_presumed"):
        CollaborativeParameters(plan_presumed=2)


def test_plan_watched_is_0_1_or_2():
    assert CollaborativeParameters(plan_watched=2).plan_watched == 2
    with pytest.raises(InvalidArgumentError, match="plan_watched"):
        CollaborativeParameters(plan_watched=3)


def test_by_default_the_planner_does_not_presume_done_a_task_its_knowers_were_seen_away_from():
    # Step 50, t1 at (3, 15) needs 2; every robot has known of it since step 0 and knows
    # the others do, and none has seen it open since step 0 (stale_after 20: by the
    # ledger alone it is presumed done). All three are seen now 17-18 m from it, 15.5 to
    # 16.5 steps from its radius: none can be there before step 65.5 > 30, so with
    # plan_watched (on) the planner keeps it open, robots 0 and 1 (nearest) head for it
    # and robot 2 explores; the rules presume it done and go only to see it (verify).
    s, view = _watched_case()
    view = view._replace(open_seen=np.zeros((3, 1), int))
    planner = PlanningCollaborativePolicy("third", CollaborativeParameters())
    planner.start(s)
    _, heads = planner.plan(view)
    assert planner.open_now.tolist() == [[True]] * 3
    assert heads.tolist() == [0, 0, -1]
    rules = make_level("collaborative", "rules")
    rules.start(s)
    _, heads = rules.plan(view)
    assert rules.open_now.tolist() == [[False]] * 3
    assert heads.tolist() == [0, 0, 0]


@pytest.mark.parametrize("missed", [False, True])
@pytest.mark.parametrize("away", [1.0, 5.0])
def test_with_plan_missed_a_teammate_not_seen_at_its_predicted_place_in_sight_is_given_up(
    missed, away
):
    # r1 at (20, 15) knows t1, r2 does not (the scene above); r1 last saw r2 at step 40
    # and predicts it ``away`` m east of itself now, at step 50, where it does not see it.
    # lost_range 0.5 x sensing 7 = 3.5 m: at 1 m r2 would be in sight, so it is not on its
    # predicted sweep and, with plan_missed, r1 gives it up for every task (no fetch
    # offered); at 5 m nothing is learnt and the fetch stays. r2 sees r1 now: not missed.
    s, view = _scene(together=False)
    view.last_seen[0, 1] = 40
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_missed=missed))
    policy.start(s)
    here = view.poses[0, :2]
    east = here + np.array([away, 0.0])
    policy.predicted = lambda view, i, j, ahead=0: east if i != j else here
    policy.plan(view)
    gone = missed and away < 3.5
    assert policy.gave_up[0, :, 1].tolist() == [gone]
    assert not policy.gave_up[1].any()
    assert [f.helper for f in policy.fetches(view, 0)] == ([] if gone else [1])
    assert CollaborativeParameters().plan_missed == 1  # on by default


@pytest.mark.parametrize("missed", [1, 2])
def test_with_plan_missed_2_a_miss_is_forgotten_after_fetch_memory_steps(missed):
    # The scene above: at step 50 r1 misses r2 1 m away (given up). Later r2's predicted
    # place is 5 m off (out of lost_range's 3.5 m), r2 still unseen since step 40. At 2 the
    # miss holds for fetch_memory = 40 steps: still given up at step 89, lifted at 90 (r2
    # may be back on its sweep); at 1 it holds until r2 is seen.
    s, view = _scene(together=False)
    view.last_seen[0, 1] = 40
    policy = PlanningCollaborativePolicy("third", CollaborativeParameters(plan_missed=missed))
    policy.start(s)
    here = view.poses[0, :2]
    place = {"east": here + np.array([1.0, 0.0])}
    policy.predicted = lambda view, i, j, ahead=0: place["east"] if i != j else here
    policy.plan(view)
    assert policy.gave_up[0, 0, 1]
    place["east"] = here + np.array([5.0, 0.0])
    given_up = []
    for step in (89, 90):
        policy.plan(view._replace(step=step))
        given_up.append(bool(policy.gave_up[0, 0, 1]))
    assert given_up == ([True, False] if missed == 2 else [True, True])
