"""``plan_claim = 4``: a teammate that does not yield a claimed goal is not a planner, so
it goes by its ad hoc types' goal (``plan(yields=(y, keeps))``, ``PlanContext.claimed``),
not by the plan's prediction of it as a planner (aif.md §6g, session 52)."""

import numpy as np
import pytest

from epistemica.aif.planning import Planner
from epistemica.aif.teammates import TYPES, adhoc_rows
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
        kept = planner.plan(0, AT, yields=([1.0, y], greedy))
        np.testing.assert_allclose(kept.G, [0.6 - np.log(y), FAR])
        assert kept.goal == goal
        plain = planner.plan(0, AT, yields=[1.0, y])
        np.testing.assert_allclose(plain.G, [0.6 - np.log(PI1[1] + y * PI1[0]), FAR])
        assert plain.goal == as_planner  # 1.14 against 1.31 at y = 0.3: the claim holds
    # An ad hoc teammate bound for goal 1 leaves goal 0 free whatever y: G(0) = 0.6.
    away = planner.plan(0, AT, yields=([1.0, 0.3], [[0.5, 0.5], [0.0, 1.0]]))
    np.testing.assert_allclose(away.G, [0.6, FAR])
    # Rows equal to the plan's prediction are plan_claim 2's mixture: the same G.
    same = planner.plan(0, AT, yields=([1.0, 0.3], [[0.5, 0.5], PI1]))
    np.testing.assert_allclose(same.G, planner.plan(0, AT, yields=[1.0, 0.3]).G)
    with pytest.raises(Exception, match="keeps"):
        planner.plan(0, AT, yields=([1.0, 0.3], [[0.5, 0.5], [-1.0, 2.0]]))


def test_the_stage_pairs_the_team_posterior_with_the_ad_hoc_rows():
    # Robot 2's types (team, greedy, convention, stationary) at (1, 4, 1, 2) / 8: P(team) =
    # 1/8, and its other types (4, 1, 2) / 7 over their rows: greedy and stationary on
    # goal 0, the convention on goal 2: (6/7, 0, 1/7).
    scenario = Scenario.paper("allocation", 3, 3, seed=0)
    log_types = np.log([[0.5, 1 / 6, 1 / 6, 1 / 6]] * 2 + [[1.0, 4.0, 1.0, 2.0]])
    probs = np.full((3, len(TYPES), 3), 1.0 / 3)
    probs[2, 1:] = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
    stage = PlanningStage(scenario, ActiveParameters(plan_claim=4), order=3)
    stage._types[0] = log_types
    stage._typing[0] = (0, np.arange(3), np.zeros((3, 2)), np.ones(3, bool), probs)
    team, rows = stage.yields(0)
    np.testing.assert_allclose(team, [0.5, 0.5, 0.125])
    np.testing.assert_allclose(rows[2], [6 / 7, 0.0, 1 / 7])
    np.testing.assert_allclose(rows[:2], 1.0 / 3)
    np.testing.assert_allclose(adhoc_rows(np.exp(log_types), probs), rows)
    stage = PlanningStage(scenario, ActiveParameters(plan_claim=3), order=3)
    stage._types[0] = log_types
    assert np.allclose(stage.yields(0), [0.5, 0.5, 0.125])  # 3: the posterior alone
