"""The planner's waiting models (epistemica.aif.plan_waiting): hand-worked cases.

Goals 0 and 1 lie 10 m apart on the x axis; robots drive at 1 m/s; horizon 3 at dt 1 s, so
waiting delays a robot by 2 s.
"""

import numpy as np
import pytest

from epistemica import InvalidArgumentError
from epistemica.aif.configurations import valid_configurations
from epistemica.aif.plan_context import PlanContext, quasi_uniform
from epistemica.aif.plan_waiting import movers, waiting
from epistemica.aif.planning import WAIT, Planner

GOALS = [[0.0, 0.0], [10.0, 0.0]]
SHARE = [[0, 1], [1, 0]]  # two robots, one goal each
MEET = [[0, 0], [1, 1]]
# Two robots side by side midway between the goals: each expects the other to reveal its
# goal by moving (evidence 0.2: eta = 2 m, so 2 s of driving is a nat), and a mismatch is
# dear (repair 3 x 10 s): waiting is worth its 2 s to each, if the other moves.
SIDE_BY_SIDE = [[5.0, 0.0], [5.0, 0.1]]
DEAR = {"evidence": 0.2, "repair": 3.0, "success_weight": 0.0}


def plan_both(model: int, order: int = 2):
    planner = Planner(GOALS, SHARE, [1.0, 1.0], order=order, horizon=3, waiting=model, **DEAR)
    return planner.plan(0, SIDE_BY_SIDE).goal, planner.plan(1, SIDE_BY_SIDE).goal


def test_two_robots_that_each_wait_for_the_other_wait_under_model_0_and_move_from_model_2():
    # Model 0: each takes the other to keep moving, so both wait (and learn nothing).
    assert plan_both(0) == (WAIT, WAIT)
    # From model 2 each predicts the other, one order down, to wait for it: a particle in
    # which the teammate waits reveals nothing and costs its delay, so both move.
    for model in (2, 3):
        assert WAIT not in plan_both(model)


def test_the_teammate_moves_as_its_own_plan_one_order_down_scores_moving_and_waiting():
    # Robot 0 at order 2 predicts robot 1 as a planner at order 1: the softmax of -G over
    # robot 1's options (each goal, and waiting) from robot 1's own plan at order 1.
    for model in (1, 3, 4):
        mine = Planner(GOALS, SHARE, [1.0, 1.0], order=2, horizon=3, waiting=model, **DEAR)
        its = Planner(GOALS, SHARE, [1.0, 1.0], order=1, horizon=3, waiting=model, **DEAR)
        theirs = its.plan(1, SIDE_BY_SIDE)
        heads = np.exp(-theirs.G).sum()
        expected = heads / (heads + np.exp(-theirs.wait))
        context = PlanContext(mine, np.array(SIDE_BY_SIDE), np.ones(2), {})
        np.testing.assert_allclose(movers(context, 0, np.ones(2)), [1.0, expected])
    assert expected < 0.5  # it waits for robot 0 more often than not


def test_below_order_two_every_teammate_moves():
    planner = Planner(GOALS, SHARE, [1.0, 1.0], order=1, horizon=3, waiting=2, **DEAR)
    context = PlanContext(planner, np.array(SIDE_BY_SIDE), np.ones(2), {})
    assert movers(context, 0, np.ones(2)).tolist() == [1.0, 1.0]


def test_a_teammate_that_waits_reveals_nothing_and_arrives_the_delay_later():
    # Rendezvous; robot 1, 20 m from goal 0 and 10 m from goal 1, is the bottleneck. With
    # it standing (move 0) nothing is revealed, so every particle takes the same goal c:
    # the meeting at c forms in the particles whose truth is c, at robot 1's arrival,
    # 2 s later under model 2 (it waits too) than under model 0. Success weight 0: the
    # realised cost is the mean of that time, or robot 0's trip + delay + repair.
    positions = np.array([[5.0, 1.0], [10.0, 20.0]])
    values = {}
    for model in (0, 2):
        planner = Planner(GOALS, MEET, [1.0, 1.0], order=1, horizon=3, waiting=model,
                          success_weight=0.0)  # fmt: skip
        context = PlanContext(planner, positions, np.ones(2), {})
        preds = np.array([[0.5, 0.5], [0.3, 0.7]])
        values[model] = waiting(context, (0,), preds, np.ones(2), np.array([1.0, 0.0]))
    # By hand: the particles' truths from the first Weyl coordinate through (0.3, 0.7).
    truth = (quasi_uniform(32, 2)[:, 0] > 0.3).astype(int)
    share = (truth == 1).mean()  # the choice: goal 1 (0.7, and nearer robot 1)
    own = np.hypot(5.0, 1.0) + 2.0
    repair = 1.5 * 10.0  # repair x the diameter at the slowest speed
    teammate = np.hypot(0.0, 20.0)
    by_hand = {delay: share * max(teammate + delay, own) + (1 - share) * (own + repair)
               for delay in (0.0, 2.0)}  # fmt: skip
    assert values[0] == pytest.approx(by_hand[0.0])
    assert values[2] == pytest.approx(by_hand[2.0])


def test_a_faint_reading_is_worth_little_once_it_is_read_with_noise():
    # Robot 0 stands midway between the two goals to share; robot 1, 30 m off, is equally
    # likely to take either. Model 0 reads any evidence, however faint, as the truth: with
    # eta 50 m or 500 m alike it values waiting as if it learnt robot 1's goal for certain
    # (every particle forms), and waits. With noise (model 4) 0.04 nats decide little.
    values = {}
    for model in (0, 4):
        for evidence in (5.0, 50.0):
            planner = Planner(GOALS, SHARE, [1.0, 1.0], order=1, horizon=3, waiting=model,
                              evidence=evidence, repair=3.0, success_weight=0.0)  # fmt: skip
            result = planner.plan(0, [[5.0, 0.0], [5.0, 30.0]])
            values[model, evidence] = (result.goal, result.wait, result.G.min())
    formed = np.hypot(5.0, 30.0) / 2.5  # every particle forms at robot 1's arrival (tau 2.5 s)
    assert values[0, 5.0][1] == pytest.approx(formed) == values[0, 50.0][1]
    assert values[0, 5.0][0] == WAIT
    for evidence in (5.0, 50.0):
        goal, wait, best = values[4, evidence]
        assert goal != WAIT and wait > best


def test_a_teammate_out_of_sight_reveals_nothing_to_a_robot_that_waits_for_it():
    # Robot 1, 30 m off and undecided, moves; eta 2 m, so 2 s of its moves nearly decide
    # its goal and robot 0 (midway) waits for them, under model 4 whether it sees robot 1
    # or not. Model 5 waits only while robot 1 is in sight: out of sight, waiting is the
    # same 2 s for nothing.
    for model, seen, waits in ((4, False, True), (5, True, True), (5, False, False)):
        planner = Planner(GOALS, SHARE, [1.0, 1.0], order=1, horizon=3, waiting=model, **DEAR)
        result = planner.plan(0, [[5.0, 0.0], [5.0, 30.0]], watching=[False, seen])
        assert (result.goal == WAIT) == waits, (model, seen)


def test_moves_read_at_the_planners_step_noise_reveal_more_than_the_positions_rate():
    # Default evidence: eta = 50 m, so 2 s of robot 1's moves are 0.04 nats at the
    # position's rate and waiting does not pay (model 5). Read as the planner reads moves
    # (steps of error sigma 0.5 m), robot 1's first steps from (5, 10) towards goal 0 or 1,
    # 53 degrees apart, tell them apart: waiting pays (model 6), though less than model 0's
    # certain reading promises.
    values = {}
    for model in (0, 5, 6):
        planner = Planner(GOALS, SHARE, [1.0, 1.0], order=1, horizon=3, waiting=model)
        values[model] = planner.plan(0, [[5.0, 0.0], [5.0, 10.0]], watching=[False, True])
    assert values[5].goal != WAIT and values[5].wait > values[5].G.min()
    assert values[6].goal == WAIT and values[0].wait < values[6].wait < values[6].G.min()


def test_with_nothing_revealed_the_posterior_estimate_is_the_plans_own_risk():
    # Four robots share four goals (24 configurations); robot 0 reads nothing (moving 0)
    # and does not wait (delay 0): the particles' choice is the plan's best goal, and model
    # 7 scores it by each particle's posterior, here the prediction itself, so the value is
    # exactly G's minimum. Model 6 scored whether 32 draws of the teammates' goals matched:
    # 2.7 s off here (the success term's -ln of a share estimated from a few matches).
    goals = [[0.0, 0.0], [10.0, 0.0], [0.0, 10.0], [10.0, 10.0]]
    table = valid_configurations("allocation", 4, 4)
    positions = np.array([[5.0, 5.0], [20.0, 20.0], [-10.0, 5.0], [5.0, -12.0]])
    values = {}
    for model in (6, 7):
        planner = Planner(goals, table, [1.0] * 4, order=1, horizon=3, waiting=model)
        context = PlanContext(planner, positions, np.ones(len(table)), {})
        G = context.costs((0,), 1)
        preds = np.stack([context.choice((0,), 1)] + [context.choice((0, j), 0) for j in (1, 2, 3)])
        values[model] = waiting(context, (0,), preds, np.zeros(4), None, 0.0) - G.min()
    assert values[7] == pytest.approx(0.0, abs=1e-9)
    assert abs(values[6]) > 1.0


def test_a_teammate_out_of_sight_gives_no_reading_not_a_noisy_one():
    # Model 6 reads a teammate's steps with noise; one out of sight gives no reading at all
    # (noise alone would favour some goal at random): waiting for it equals heading now
    # but for the delay, so with robot 0 not the bottleneck the two are equal.
    planner = Planner(GOALS, SHARE, [1.0, 1.0], order=1, horizon=3, waiting=7)
    context = PlanContext(planner, np.array([[5.0, 0.0], [5.0, 30.0]]), np.ones(2), {})
    preds = np.array([[0.5, 0.5], [0.5, 0.5]])
    wait = waiting(context, (0,), preds, np.zeros(2))
    assert wait == pytest.approx(waiting(context, (0,), preds, np.zeros(2), None, 0.0))


def test_heading_off_reads_the_teammate_too_so_waiting_pays_only_where_standing_saves_time():
    # Robot 0 midway between the two goals to share, robot 1 in sight and undecided.
    # Model 7 prices waiting against heading now for good: robot 1's first steps would tell
    # its goal, so it waits. Model 8 prices it against heading for a goal for the same 2 s
    # and choosing again: 10 m off, robot 1 is the bottleneck and robot 0's detour of 2 m
    # back costs nothing, so heading is as good (a tie, which goes to heading); 4 m off,
    # robot 0 may be the later one, and standing midway saves the detour: it waits.
    def plan(model, teammate):
        planner = Planner(GOALS, SHARE, [1.0, 1.0], order=1, horizon=3, waiting=model)
        return planner.plan(0, [[5.0, 0.0], teammate], watching=[False, True])

    assert plan(7, [5.0, 10.0]).goal == WAIT
    far = plan(8, [5.0, 10.0])
    assert far.goal != WAIT and far.wait > far.G.min()
    near = plan(8, [5.0, 4.0])
    assert near.goal == WAIT and plan(7, [5.0, 4.0]).wait < near.wait < near.G.min()


def test_waiting_model_is_checked():
    with pytest.raises(InvalidArgumentError, match="waiting"):
        Planner(GOALS, SHARE, [1.0, 1.0], waiting=9)


def test_the_levels_planner_takes_the_waiting_model_of_its_parameters():
    from epistemica.sim import Scenario
    from epistemica.sim.policies.parameters import ActiveParameters
    from epistemica.sim.policies.planning import PlanningStage

    scenario = Scenario.paper("allocation", 2, 2, seed=0)
    assert ActiveParameters().plan_wait == 8
    for model in (0, 8):
        stage = PlanningStage(scenario, ActiveParameters(plan_wait=model), order=3)
        assert stage.options["waiting"] == model
    with pytest.raises(InvalidArgumentError, match="plan_wait"):
        ActiveParameters(plan_wait=9)
