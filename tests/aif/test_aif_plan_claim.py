"""Contested goals priced by arrival (``Planner(claim=...)``, ``plan_claim``): a teammate
that would reach the robot's goal after it, and shares that goal with it in no
configuration, is predicted as going elsewhere (it finds the robot settled there), with
the probability that it yields, a planner (``plan(yields=...)``, ``plan_claim = 2``)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif.plan_context import contests, later_claimants
from epistemica.aif.planning import Planner
from epistemica.sim import Scenario
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage

GOALS = [[0.0, 0.0], [10.0, 0.0]]
SWAP = [[0, 1], [1, 0]]  # allocation of two robots to two goals
MEET = [[0, 0], [1, 1]]  # rendezvous of two robots at one of two goals
AT = [[2.0, 0.0], [4.0, 0.0]]  # robot 0 2 m from goal 0, robot 1 4 m from it
# Unit speeds, tau = 10 s (temperature 1, goals 10 m apart), eta = 5 m (evidence 0.5).
WORKED = dict(order=1, temperature=1.0, evidence=0.5)


def test_a_later_teammate_on_the_robots_goal_is_predicted_elsewhere():
    # Robot 1 at order 0: the uniform prior times exp(-d / 5):
    # pi_1 = (e^-0.8, e^-1.2) / sum = (0.5987, 0.4013).
    pi1 = np.exp([-0.8, -1.2]) / np.exp([-0.8, -1.2]).sum()
    # Without claims, goal 0 forms only if robot 1 takes goal 1, at max(2, 6) = 6 s:
    # G(0) = 6 / 10 - ln 0.4013 = 1.513; goal 1 at max(8, 4) = 8 s: G(1) = 0.8 - ln 0.5987
    # = 1.313. The robot leaves its near goal for the far one.
    plain = Planner(GOALS, SWAP, [1.0, 1.0], **WORKED).plan(0, AT)
    assert plain.goal == 1
    np.testing.assert_allclose(plain.G, [0.6 - np.log(pi1[1]), 0.8 - np.log(pi1[0])])
    # With claims robot 1, 4 s from goal 0 against robot 0's 2 s, finds goal 0 taken:
    # conditioned on not taking it, it takes goal 1 with probability 1, so G(0) = 0.6.
    # At goal 1 robot 1 (6 s) is earlier than robot 0 (8 s): G(1) is unchanged.
    claimed = Planner(GOALS, SWAP, [1.0, 1.0], claim=True, **WORKED).plan(0, AT)
    assert claimed.goal == 0
    np.testing.assert_allclose(claimed.G, [0.6, 0.8 - np.log(pi1[0])])


def test_only_the_goals_the_robot_reaches_first_are_claimed():
    # Mirror: robot 0 at 4 m from goal 0, robot 1 at 2 m; pi_1 = (e^-0.4, e^-1.6) / sum.
    there = [[4.0, 0.0], [2.0, 0.0]]
    pi1 = np.exp([-0.4, -1.6]) / np.exp([-0.4, -1.6]).sum()
    claimed = Planner(GOALS, SWAP, [1.0, 1.0], claim=True, **WORKED).plan(0, there)
    # Goal 0: robot 1 is there first (2 s against 4 s), its prediction stands:
    # G(0) = max(4, 8) / 10 - ln pi_1(1). Goal 1: robot 0 is first (6 s against 8 s), so
    # robot 1 is predicted at goal 0: G(1) = max(6, 2) / 10 = 0.6.
    np.testing.assert_allclose(claimed.G, [0.8 - np.log(pi1[1]), 0.6])


def test_a_goal_shared_in_a_configuration_is_not_contested():
    # Rendezvous: robot 1 at goal 0 is the meeting, not a conflict.
    plain = Planner(GOALS, MEET, [1.0, 1.0], **WORKED).plan(0, AT)
    claimed = Planner(GOALS, MEET, [1.0, 1.0], claim=True, **WORKED).plan(0, AT)
    np.testing.assert_allclose(claimed.G, plain.G)


def test_a_teammate_that_never_yields_keeps_its_prediction():
    # Robot 1 yields with probability y (a planner) or keeps pi_1 (an ad hoc teammate):
    # goal 0 forms if robot 1 takes goal 1 anyway, or would have taken goal 0 and yields,
    # P(0) = pi_1(1) + y pi_1(0), at 6 s: G(0) = 0.6 - ln(pi_1(1) + y pi_1(0)).
    pi1 = np.exp([-0.8, -1.2]) / np.exp([-0.8, -1.2]).sum()
    planner = Planner(GOALS, SWAP, [1.0, 1.0], claim=True, **WORKED)
    far = 0.8 - np.log(pi1[0])  # goal 1: robot 1 is earlier there, nothing conditioned
    for y, goal in ((0.0, 1), (0.5, 0), (1.0, 0)):
        result = planner.plan(0, AT, yields=[0.3, y])  # the robot's own entry is ignored
        np.testing.assert_allclose(result.G, [0.6 - np.log(pi1[1] + y * pi1[0]), far])
        assert result.goal == goal
    # y = 0 is the plan without claims; y = 1 the claim of every later teammate.
    plain = Planner(GOALS, SWAP, [1.0, 1.0], **WORKED).plan(0, AT)
    np.testing.assert_allclose(planner.plan(0, AT, yields=[1.0, 0.0]).G, plain.G)
    np.testing.assert_allclose(planner.plan(0, AT, yields=[1.0, 1.0]).G, planner.plan(0, AT).G)
    with pytest.raises(Exception, match="yields"):
        planner.plan(0, AT, yields=[1.0, 1.5])


def test_the_stage_reads_yields_from_the_type_posterior():
    # Types (team, greedy, convention, stationary) with log weights: robot 1 at the prior
    # (1/2, 1/6, 1/6, 1/6), robot 2 at (1, 4, 1, 2) / 8, so P(team) = 1/2 and 1/8.
    scenario = Scenario.paper("allocation", 3, 3, seed=0)
    log_types = np.log([[0.5, 1 / 6, 1 / 6, 1 / 6]] * 2 + [[1.0, 4.0, 1.0, 2.0]])
    for claim, expected in ((1, None), (2, [0.5, 0.5, 0.125])):
        stage = PlanningStage(scenario, ActiveParameters(plan_claim=claim), order=3)
        stage._types[0] = log_types
        got = stage.yields(0)
        assert got is expected if expected is None else np.allclose(got.yields, expected)
    stage = PlanningStage(scenario, ActiveParameters(plan_claim=2, plan_types=0.0), order=3)
    assert stage.yields(0) is None  # types off: everyone is a planner


def test_plan_claim_is_six_by_default_and_takes_seven_values():
    assert ActiveParameters().plan_claim == 6  # on since session 52; 0 is the ablation
    assert ActiveParameters(plan_claim=0).plan_claim == 0
    assert ActiveParameters(plan_claim=2).plan_claim == 2
    assert ActiveParameters(plan_claim=3).plan_claim == 3
    for bad in (True, 7, -1, 1.5):
        with pytest.raises(Exception, match="plan_claim"):
            ActiveParameters(plan_claim=bad)


@settings(max_examples=60, deadline=None)
@given(
    st.integers(2, 4).flatmap(
        lambda n: st.tuples(
            st.just(n),
            st.lists(st.lists(st.integers(0, 2), min_size=n, max_size=n), min_size=1, max_size=6),
            st.lists(st.floats(0.0, 9.0), min_size=3 * n, max_size=3 * n),
            st.integers(0, n - 1),
        )
    )
)
def test_contests_is_later_claimants_of_every_goal(case):
    # The vectorised table (one pass over the rows) against the one-goal function, goal
    # by goal: the same teammates, and none for a goal no row gives the robot.
    n, rows, times, robot = case
    rows, times = np.array(rows), np.array(times).reshape(n, 3)
    table = contests(times, robot, rows)
    for goal in range(3):
        expected = later_claimants(times[:, goal], robot, goal, rows)
        if not (rows[:, robot] == goal).any():
            expected = np.zeros(n, dtype=bool)
        assert table[goal].tolist() == expected.tolist()
