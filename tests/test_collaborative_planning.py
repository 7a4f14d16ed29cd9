"""The collaborative planning levels (sim/policies/collaborative_planning.py): registered
beside the rules, deciding by what the robot knows its teammates know, and closed loop."""

import numpy as np
import pytest

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
