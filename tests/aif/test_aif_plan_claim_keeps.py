"""``plan_claim = 4``: a teammate that does not yield a claimed goal is not a planner, so
it goes by its ad hoc types' goal (``plan(yields=ClaimModel(y, keeps))``, ``PlanContext.claimed``),
not by the plan's prediction of it as a planner; ``plan_claim = 5``: and the stationary type
may drive to a goal before it stands (aif.md §6g, session 52)."""

import numpy as np
import pytest

from epistemica.aif.planning import Planner
from epistemica.aif.teammates import (
    TYPE_PRIOR,
    TYPES,
    ClaimModel,
    adhoc_rows,
    motion_log_likelihood,
    update_types,
)
from epistemica.sim import Scenario
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage

GOALS = [[0.0, 0.0], [10.0, 0.0]]
SWAP = [[0, 1], [1, 0]]  # allocation of two robots to two goals
AT = [[2.0, 0.0], [4.0, 0.0]]  # robot 0 2 m from goal 0, robot 1 4 m from it
# Unit speeds, tau = 10 s (temperature 1, goals 10 m apart), eta = 5 m (evidence 0.5).
WORKED = dict(order=1, temperature=1.0, evidence=0.5, claim=True)
# Robot 1 at order 0: the uniform prior times exp(-d / 5), pi_1 = (0.5987, 0.4013).
PI1 = np.exp([-0.8, -1.2]) / np.exp([-0.8, -1.2]).sum()
FAR = 0.8 - np.log(PI1[0])  # goal 1: robot 1 is there first (6 s against 8 s), unclaimed


def test_a_teammate_that_does_not_yield_goes_by_its_ad_hoc_types():
    # Greedy robot 1 (its nearest goal is goal 0) yields with y. If it does not, it comes
    # to goal 0, so goal 0 forms only if it yields: P(0) = y, at max(2, 6) = 6 s,
    # G(0) = 0.6 - ln y. Kept as a planner (plan_claim 2 / 3), P(0) = pi_1(1) + y pi_1(0).
    planner = Planner(GOALS, SWAP, [1.0, 1.0], **WORKED)
    greedy = [[0.5, 0.5], [1.0, 0.0]]  # the robot's own row is never read
    for y, goal, as_planner in ((0.3, 1, 0), (0.8, 0, 0)):
        kept = planner.plan(0, AT, yields=ClaimModel([1.0, y], greedy))
        np.testing.assert_allclose(kept.G, [0.6 - np.log(y), FAR])
        assert kept.goal == goal
        plain = planner.plan(0, AT, yields=[1.0, y])
        np.testing.assert_allclose(plain.G, [0.6 - np.log(PI1[1] + y * PI1[0]), FAR])
        assert plain.goal == as_planner  # 1.14 against 1.31 at y = 0.3: the claim holds
    # An ad hoc teammate bound for goal 1 leaves goal 0 free whatever y: G(0) = 0.6.
    away = planner.plan(0, AT, yields=ClaimModel([1.0, 0.3], [[0.5, 0.5], [0.0, 1.0]]))
    np.testing.assert_allclose(away.G, [0.6, FAR])
    # Rows equal to the plan's prediction are plan_claim 2's mixture: the same G.
    same = planner.plan(0, AT, yields=ClaimModel([1.0, 0.3], [[0.5, 0.5], PI1]))
    np.testing.assert_allclose(same.G, planner.plan(0, AT, yields=[1.0, 0.3]).G)
    with pytest.raises(Exception, match="keeps"):
        planner.plan(0, AT, yields=ClaimModel([1.0, 0.3], [[0.5, 0.5], [-1.0, 2.0]]))


def test_the_stage_pairs_the_team_posterior_with_the_ad_hoc_rows():
    # Robot 2's types (team, greedy, convention, stationary) at (1, 4, 1, 2) / 8: P(team) =
    # 1/8, and its other types (4, 1, 2) / 7 over their rows: greedy and stationary on
    # goal 0, the convention on goal 2: (6/7, 0, 1/7).
    scenario = Scenario.paper("allocation", 3, 3, seed=0)
    log_types = np.log([[0.5, 1 / 6, 1 / 6, 1 / 6]] * 2 + [[1.0, 4.0, 1.0, 2.0]])
    probs = np.full((3, len(TYPES), 3), 1.0 / 3)
    probs[2, 1:] = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
    never = np.array([0, -1, 0])  # when the robot last saw each robot: robot 1 never
    for claim in (4, 6):
        stage = PlanningStage(scenario, ActiveParameters(plan_claim=claim), order=3)
        stage._types[0] = log_types
        stage._typing[0] = (0, np.arange(3), np.zeros((3, 2)), np.ones(3, bool), probs)
        stage._last[0] = (0, np.zeros((3, 2)), never)
        team, rows, within = stage.yields(0)
        np.testing.assert_allclose(team, [0.5, 0.5, 0.125])
        np.testing.assert_allclose(rows[2], [6 / 7, 0.0, 1 / 7])
        np.testing.assert_allclose(rows[0], 1.0 / 3)
        # At 6 a teammate never seen has no ad hoc row (nan: it keeps the plan's).
        assert np.isnan(rows[1]).all() == (claim == 6) and within == (claim == 6)
    np.testing.assert_allclose(adhoc_rows(np.exp(log_types), probs)[[0, 2]], rows[[0, 2]])
    stage = PlanningStage(scenario, ActiveParameters(plan_claim=3), order=3)
    stage._types[0] = log_types
    assert np.allclose(stage.yields(0).yields, [0.5, 0.5, 0.125])  # 3: the posterior alone
    assert stage.yields(0).keeps is None


def test_a_stationary_teammate_driving_to_the_claimed_goal_is_not_read_as_yielding():
    # plan_claim 5: the stationary type is the simulator's (to a goal drawn at random, then
    # still). Teammate at the origin steps 1 m (reach 1, sigma 0.5) towards goal 0 at
    # (10, 0), the robot's claimed goal; goal 1 at (0, -5) is its nearest. Team (yielded),
    # greedy and convention all say goal 1: a miss of sqrt 2 m, -4 nats. Standing still
    # misses by 1 m, -2; driving, ln(e^-2 / 2 + (1 + e^-4) / 4) = -1.13 (to goal 0 or 1).
    goals = np.array([[10.0, 0.0], [0.0, -5.0]])
    probs = np.zeros((1, len(TYPES), 2))
    probs[0, :, 1] = 1.0
    args = np.zeros((1, 2)), np.array([[1.0, 0.0]]), probs, goals, np.ones(1), 0.5
    miss, still = np.exp(-4.0), np.exp(-2.0)
    drive = still / 2 + (1 + miss) / 4
    for driving, stationary in ((False, still), (True, drive)):
        ll = motion_log_likelihood(*args, drive=driving)
        team = np.exp(update_types(np.log(TYPE_PRIOR)[None], ll, 0.0))[0, 0]
        assert np.isclose(team, 0.5 * miss / (0.5 * miss + (2 * miss + stationary) / 6))
    # P(team) 0.24 standing still, 0.13 driving: the claim assumes a yield half as often.
    scenario = Scenario.paper("allocation", 3, 3, seed=0)
    flags = [PlanningStage(scenario, ActiveParameters(plan_claim=c), 3).driving for c in (4, 5)]
    assert flags == [False, True]


def test_a_teammate_never_seen_keeps_its_prediction_and_ad_hoc_rows_stay_in_its_set():
    # plan_claim 6. Robot 1 does not know goal 2 (its chain's set): predicted at order 1,
    # pi_1(2) = 0. Robot 0 2 m from goal 0, robot 1 4 m (later): goal 0 is claimed.
    goals = [[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]]
    rows = np.array([[a, b] for a in range(3) for b in range(3) if a != b])
    planner = Planner(goals, rows, [1.0, 1.0], **{**WORKED, "order": 2}, hierarchy=0.0)
    sets = {(0, 1): rows[:, 1] != 2}
    pi1 = planner.plan(0, AT, sets=sets).predictions[1]
    assert pi1[2] == 0.0
    mine = [1 / 3] * 3  # the robot's own row is never read
    # y = 0 and ad hoc rows on goal 2, which it does not know: taken as they are, goal 0
    # forms with it at goal 2 for sure, at max(2, sqrt(4^2 + 10^2)) = 10.77 s: G(0) = 1.077.
    loose = planner.plan(0, AT, sets=sets, yields=ClaimModel([1.0, 0.0], [mine, [0.0, 0.0, 1.0]]))
    assert np.isclose(loose.G[0], np.hypot(4.0, 10.0) / 10)
    # Kept within its set, nothing is left of that row: it keeps pi_1, as a nan row does
    # and as plan_claim 2 does at y = 0: G(0) = max(2, 6) / 10 - ln pi_1(1).
    within = planner.plan(
        0, AT, sets=sets, yields=ClaimModel([1.0, 0.0], [mine, [0.0, 0.0, 1.0]], True)
    )
    unread = planner.plan(0, AT, sets=sets, yields=ClaimModel([1.0, 0.0], [mine, [np.nan] * 3]))
    plain = planner.plan(0, AT, sets=sets, yields=[1.0, 0.0])
    for result in (within, unread):
        np.testing.assert_allclose(result.G, plain.G)
    assert np.isclose(within.G[0], 0.6 - np.log(pi1[1]))
    # Half on goal 0, half on goal 2: within its set all of it comes to goal 0, P(0) = 0.
    half = [0.5, 0.0, 0.5]
    assert (
        planner.plan(0, AT, sets=sets, yields=ClaimModel([1.0, 0.0], [mine, half], True)).G[0] > 20
    )
    assert planner.plan(0, AT, sets=sets, yields=ClaimModel([1.0, 0.0], [mine, half])).G[0] < 2
