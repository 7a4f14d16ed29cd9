"""The goal missions' oracle (sim/policies/oracle.py): the least-makespan configuration,
worked by hand and against brute force, and the full view the trial loop gives it."""

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.mission import parse_mission
from epistemica.sim import simulate
from epistemica.sim.engine.navigation import Roadmap
from epistemica.sim.engine.obstacles import polygon
from epistemica.sim.kinds.goal import CAPACITY, RENDEZVOUS
from epistemica.sim.policies.oracle import least_makespan


def test_allocation_takes_the_assignment_whose_last_arrival_is_soonest():
    # Least total: r0-g0, r1-g1, r2-g2 = 1 + 1 + 9 = 11, last at 9. The oracle's:
    # r0-g2, r1-g0, r2-g1 = 4 + 3 + 5, last at 5 (total 12).
    cost = np.array([[1.0, 2.0, 4.0], [3.0, 1.0, 6.0], [8.0, 5.0, 9.0]])
    assert least_makespan(cost, np.array([0, 1, 2])).tolist() == [2, 0, 1]


def test_ties_in_the_last_arrival_go_to_the_least_total():
    # Both assignments end at 5; r0-g0, r1-g1 totals 1 + 5, the other 5 + 5.
    cost = np.array([[1.0, 5.0], [5.0, 5.0]])
    assert least_makespan(cost, np.array([3, 7])).tolist() == [3, 7]


def test_a_robot_left_without_a_goal_takes_its_nearest():
    cost = np.array([[1.0], [2.0], [0.5]])
    # One goal: the robot nearest it (r2) is assigned; the others head for it too.
    assert least_makespan(cost, np.array([4])).tolist() == [4, 4, 4]


def test_rendezvous_and_capacities():
    # Goal 0: farthest robot 9 away; goal 1: 6. The oracle meets at goal 1.
    cost = np.array([[1.0, 6.0], [9.0, 5.0], [2.0, 6.0]])
    assert least_makespan(cost, np.array([0, 1]), RENDEZVOUS).tolist() == [1, 1, 1]
    # Capacity 2 at goal 0 and 1 at goal 1: r1 (9 from goal 0) takes goal 1.
    got = least_makespan(cost, np.array([0, 1]), CAPACITY, capacities=[2, 1])
    assert got.tolist() == [0, 1, 0]


def test_a_table_of_valid_configurations_is_searched_over_the_open_goals():
    cost = np.array([[1.0, 2.0, 7.0], [3.0, 1.0, 2.0]])  # goals 5, 6, 8
    table = np.array([[5, 6], [6, 8], [9, 5]])  # the last uses a goal not open
    # [5, 6]: last at 1; [6, 8]: last at 2.
    assert least_makespan(cost, np.array([5, 6, 8]), table=table).tolist() == [5, 6]


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 4).flatmap(
        lambda n: st.integers(n, 5).flatmap(
            lambda m: st.lists(st.integers(1, 30).map(float), min_size=n * m, max_size=n * m).map(
                lambda v: np.array(v).reshape(n, m)
            )
        )
    )
)
def test_the_bottleneck_matches_brute_force(cost):
    n, m = cost.shape
    goals = np.arange(m) + 10
    row = least_makespan(cost, goals) - 10
    assert len(set(row.tolist())) == n  # distinct goals
    ways = [cost[np.arange(n), list(p)] for p in itertools.permutations(range(m), n)]
    best = min(w.max() for w in ways)
    least_total = min(w.sum() for w in ways if w.max() == best)
    got = cost[np.arange(n), row]
    assert got.max() == best and got.sum() == least_total


PRIVATE = """\
mission allocation
workspace 30
robot r1: range at (2, 2)
robot r2: range at (28, 2)
goal g1 at (4, 26)
goal g2 at (26, 26)
goal g3 at (15, 15) closed
knows r1: g2
knows r2: g1
sensing model paper noise 0.5 range 6 discovery 3
simulate trials 1 seed 0 steps 80 levels convention
"""


def test_the_oracle_knows_what_no_robot_was_told():
    scenario = parse_mission(PRIVATE).scenario(0)
    trial = simulate(scenario, "oracle", seed=0)
    # Each robot knows only the goal across the workspace; the oracle sends each to the
    # goal straight above it (24 m against 34.2 m) and never to the closed g3.
    assert trial.success
    assert trial.focal[0, 0].tolist() == [0, 1] and trial.focal[0, 1].tolist() == [0, 1]
    assert not (trial.focal == 2).any()
    # 24 m at the scenario's top speed, plus a few steps to turn first.
    assert trial.steps <= np.ceil(24.0 / (scenario.max_speed[0] * scenario.dt)) + 6


WALLED = """\
mission rendezvous
workspace 30
robot r1: range at (5, 10)
goal g1 at (10, 10)
goal g2 at (5, 22)
obstacle (7, 0) (8, 0) (8, 20) (7, 20)
simulate trials 1 seed 0 steps 80 levels convention
"""


def test_ways_are_measured_round_the_walls():
    scenario = parse_mission(WALLED).scenario(0)
    # g1 is 5 m away in a straight line, 2 * hypot(2.5, 10.5) ~ 21.6 m round the wall's top;
    # g2 is 12 m away in the open.
    roadmap = Roadmap(scenario.obstacles, margin=0.5, workspace=30.0)
    ways = roadmap.lengths(scenario.starts[:, :2], scenario.goals)
    assert ways[0, 0] > 20 and np.isclose(ways[0, 1], 12.0)
    trial = simulate(scenario, "oracle", seed=0)
    assert trial.success and trial.focal[0, 0, 0] == 1


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.0, 20.0), min_size=4, max_size=4))
def test_a_way_is_never_shorter_than_the_straight_line(xy):
    block = polygon([[9, 9], [11, 9], [11, 11], [9, 11]])
    roadmap = Roadmap((block,), margin=0.5, workspace=20.0)
    start, goal = np.array(xy[:2]), np.array(xy[2:])
    way = roadmap.lengths(start[None], goal[None])[0, 0]
    assert way >= np.hypot(*(goal - start)) - 1e-9
