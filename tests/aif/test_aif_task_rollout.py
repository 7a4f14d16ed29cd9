"""The rollout valuation of collaborative options (epistemica.aif.task_rollout): chains of
fetches worked by hand, the orders' views, and laws of the event-driven team model."""

import numpy as np
import pytest

from epistemica import InvalidArgumentError
from epistemica.aif.task_planning import Fetch, TaskPlanner
from epistemica.aif.task_rollout import Geometry, Leg, rollout_total, rollout_values, team_views

HORIZON = 100.0


def _gap(a, b) -> float:
    return float(np.hypot(*(np.asarray(a, dtype=float) - np.asarray(b, dtype=float))))


def _chain():
    """Robot 0 alone knows of a task needing 3 at its feet; 1 and 2 along a line."""
    robots = [[0.0, 0.0], [10.0, 0.0], [20.0, 0.0]]
    geometry = Geometry(robots, [[0.0, 0.0]], [1.0, 1.0, 1.0])
    sets = {(0,): [True], (0, 1): [False], (0, 2): [False]}
    return robots, geometry, sets


def test_a_chain_of_fetches_worked_by_hand():
    robots, geometry, sets = _chain()
    task = (0.0, 0.0)
    # fetch 1: meet it, then robot 0 (the lower index of the two knowers there, equally
    # near robot 2) fetches 2 while robot 1 goes to wait; the task is done at the last
    # arrival.
    met1 = _gap(robots[0], robots[1])
    met2 = met1 + _gap(robots[1], robots[2])
    via1 = max(met2 + _gap(robots[2], task), met2 + _gap(robots[1], task))
    # fetch 2 first: then robot 0 (the lower index of the two knowers at 2's place, equally
    # near robot 1) fetches 1, while robot 2 goes to the task to wait.
    met2 = _gap(robots[0], robots[2])
    met1 = met2 + _gap(robots[2], robots[1])
    via2 = max(met1 + _gap(robots[1], task), met2 + _gap(robots[2], task))
    go, fetch = rollout_values(0, geometry, sets, [3], HORIZON, 2, [1, 2])
    # nobody else ever learns of the task: going and taking no part both cost the horizon
    assert go.tolist() == [0.0]
    assert fetch.tolist() == pytest.approx([via1 - HORIZON, via2 - HORIZON])
    assert fetch.min() < go.min()


def test_the_one_step_planner_sees_no_value_in_the_chain_and_the_rollout_does():
    robots, geometry, sets = _chain()
    speed = 1.0
    fetches = [
        Fetch(0, h, 2 * _gap(robots[0], robots[h]), 2 * _gap(robots[0], robots[h]), 1.0)
        for h in (1, 2)
    ]
    arrivals = [[_gap(r, (0.0, 0.0)) / speed] for r in robots]
    unknown = {(0, 1): 1, (0, 2): 1}
    one_step = TaskPlanner([3], order=2, temperature=1.0, fail=[HORIZON])
    plan = one_step.plan(0, arrivals, sets, unknown, fetches)
    assert plan.kind == "explore"  # a fetch brings one of the two robots the task lacks
    assert min(plan.G[2:]) >= plan.G[1]
    rollout = TaskPlanner([3], order=2, temperature=1.0, fail=[HORIZON], rollout=HORIZON)
    plan = rollout.plan(0, arrivals, sets, unknown, fetches, geometry=geometry)
    assert (plan.kind, plan.helper) == ("fetch", 1)
    via1 = rollout_values(0, geometry, sets, [3], HORIZON, 2, [1])[1][0]
    assert plan.G[2] == pytest.approx(via1)  # tau 1: nats are steps
    # without the geometry the rollout planner is the one-step planner
    assert rollout.plan(0, arrivals, sets, unknown, fetches).G.tolist() == (
        one_step.plan(0, arrivals, sets, unknown, fetches).G.tolist()
    )


def test_the_order_decides_what_a_teammate_thinks_a_third_knows():
    # Robots 0 and 1 know of a task needing 3; robot 1 (at order 3) wrongly thinks robot 2
    # knows too, so it goes to the task rather than fetching 2, and the task never fills.
    robots = [[0.0, 0.0], [10.0, 0.0], [20.0, 0.0]]
    geometry = Geometry(robots, [[0.0, 0.0]], [1.0, 1.0, 1.0])
    sets = {(0,): [True], (0, 1): [True], (0, 2): [False], (0, 1, 2): [True]}
    go2, _ = rollout_values(0, geometry, sets, [3], HORIZON, 2)
    go3, _ = rollout_values(0, geometry, sets, [3], HORIZON, 3)
    # order 2: robot 1 fetches 2 (met at 10), both then go; robot 0 is there at 0
    done = _gap(robots[1], robots[2]) + _gap(robots[2], (0.0, 0.0))
    absent = HORIZON  # without robot 0 only two robots ever know of it
    assert go2.tolist() == pytest.approx([done - absent])
    assert go3.tolist() == [0.0]


def test_team_views_fall_back_to_the_shorter_chain():
    sets = {(0,): [True, True], (0, 1): [True, False], (0, 1, 2): [False, True]}
    K, V = team_views(0, 3, sets, 3)
    assert K.tolist() == [[True, True], [True, False], [True, True]]  # (0, 2): (0,)
    assert V[1, 2].tolist() == [False, True]  # (0, 1, 2)
    assert V[1, 0].tolist() == K[0].tolist()  # (0, 1, 0) missing: (0, 0) is K[0]
    assert V[1, 1].tolist() == K[1].tolist()
    K2, V2 = team_views(0, 3, sets, 2)
    assert (K2 == K).all() and all((V2[j] == K).all() for j in range(3))


@pytest.mark.parametrize("seed", range(20))
def test_arriving_sooner_never_finishes_a_task_later(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 7))
    needs = np.array([int(rng.integers(1, n + 1))])
    task = rng.uniform(0, 50, (1, 2))
    where = rng.uniform(0, 50, (n, 2))
    speed = rng.uniform(0.5, 2.0, n)
    known = rng.random(n) < 0.6
    known[0] = True
    K = known[:, None]
    V = np.broadcast_to(K, (n, n, 1)).copy()
    geometry = Geometry(where, task, speed)
    before = rollout_total(0, Leg("task", 0), where, geometry, needs, HORIZON, K, V, True)
    nearer = where.copy()
    nearer[0] = task[0] + rng.uniform(0.0, 1.0) * (where[0] - task[0])
    after = rollout_total(0, Leg("task", 0), nearer, geometry, needs, HORIZON, K, V, True)
    assert after <= before + 1e-9


@pytest.mark.parametrize("seed", range(20))
def test_values_are_finite_and_bounded_by_the_horizon(seed):
    rng = np.random.default_rng(100 + seed)
    n, m = int(rng.integers(2, 8)), int(rng.integers(1, 5))
    geometry = Geometry(rng.uniform(0, 40, (n, 2)), rng.uniform(0, 40, (m, 2)), np.full(n, 0.7))
    known = rng.random((n, n, m)) < 0.5
    robot = int(rng.integers(n))
    sets = {(robot,): known[robot, robot]}
    for j in range(n):
        sets[(robot, j)] = known[robot, j] & known[robot, robot]
        for k in range(n):
            sets[(robot, j, k)] = known[j, k]
    needs = rng.integers(1, n + 1, m)
    helpers = [h for h in range(n) if h != robot]
    for order in (1, 2, 3):
        go, fetch = rollout_values(robot, geometry, sets, needs, HORIZON, order, helpers)
        mine = known[robot, robot]
        assert np.isinf(go[~mine]).all()
        values = np.concatenate([go[mine], fetch])
        assert np.isfinite(values).all()
        assert (np.abs(values) <= HORIZON * mine.sum() + 1e-9).all()


def test_particles_are_averaged():
    _, geometry, sets = _chain()
    near = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 0.0]])
    far = np.array([[0.0, 0.0], [30.0, 0.0], [40.0, 0.0]])
    one = [
        rollout_values(0, geometry._replace(positions=p), sets, [3], HORIZON, 2, [1, 2])[1]
        for p in (near, far)
    ]
    both = geometry._replace(positions=[near, far])
    assert rollout_values(0, both, sets, [3], HORIZON, 2, [1, 2])[1] == pytest.approx(
        (one[0] + one[1]) / 2
    )


def test_bad_arguments_are_refused():
    _, geometry, sets = _chain()
    with pytest.raises(InvalidArgumentError):
        rollout_values(0, geometry._replace(tasks=[[0.0, 0.0, 0.0]]), sets, [3], HORIZON, 2)
    with pytest.raises(InvalidArgumentError):
        rollout_values(0, geometry, sets, [3], 0.0, 2)
    with pytest.raises(InvalidArgumentError):
        rollout_values(0, geometry, sets, [3], [100.0, 100.0], 2)
    with pytest.raises(InvalidArgumentError):
        TaskPlanner([3], rollout=np.nan)


def test_mixed_orders_average_the_rollouts_of_orders_two_and_three():
    robots = [[0.0, 0.0], [10.0, 0.0], [20.0, 0.0]]
    geometry = Geometry(robots, [[0.0, 0.0]], [1.0, 1.0, 1.0])
    sets = {(0,): [True], (0, 1): [True], (0, 2): [False], (0, 1, 2): [True]}
    two = rollout_values(0, geometry, sets, [3], HORIZON, 2)[0]
    three = rollout_values(0, geometry, sets, [3], HORIZON, 3)[0]
    assert two[0] != three[0]
    mixed = rollout_values(0, geometry, sets, [3], HORIZON, 3, mixed=True)[0]
    assert mixed.tolist() == pytest.approx(((two + three) / 2).tolist())
    assert rollout_values(0, geometry, sets, [3], HORIZON, 2, mixed=True)[0].tolist() == (
        two.tolist()
    )
