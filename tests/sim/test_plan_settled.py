"""Anchors read from settles (``plan_settled``): a teammate seen settled, plan after plan,
at a goal away from the robot's own holds to it, and every chain's set is held there
(``PlanningStage.anchors``, ``configuration_sets.held_to``)."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.del_.errors import EpistemicaError
from epistemica.sim import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.configuration_sets import NestedSets, held_to
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage


def _stage(kind: str = "rendezvous", settled: int = 3) -> tuple[PlanningStage, Scenario]:
    scenario = Scenario.paper(kind, 3, 3, seed=0)
    return PlanningStage(scenario, ActiveParameters(plan_settled=settled), order=3), scenario


def _seen(scenario: Scenario, step: int, settles_of_r1) -> Observations:
    """r1 stands on goal 0 (heading for it); it sees r2 and r3 settle as given."""
    poses = np.zeros((3, 3, 3))
    poses[0, 0, :2] = scenario.goals[0]
    settles = np.full((3, 3), -1)
    settles[0] = settles_of_r1
    seen = np.ones((3, 3), dtype=bool)
    known = np.ones((3, 3), dtype=bool)
    return Observations(step, poses, seen, np.full((3, 3), step), known, ~known, None, settles)


def _run(stage, scenario, sequence) -> list[dict]:
    stage._heading[0] = 0
    return [stage.anchors(_seen(scenario, k, row), 0) for k, row in enumerate(sequence)]


def test_a_teammate_settled_away_for_three_plans_is_an_anchor():
    stage, scenario = _stage()
    # r2 settles at goal 2 (away from r1's goal 0) at plans 0, 1, 3; at plan 2 its settle
    # is not seen (counts nothing, resets nothing). r3 settles at goal 0, r1's own goal.
    out = _run(stage, scenario, [[-1, 2, 0], [-1, 2, 0], [-1, -1, 0], [-1, 2, 0]])
    assert out == [{}, {}, {}, {1: 2}]


def test_a_settle_at_another_goal_starts_the_count_anew():
    stage, scenario = _stage()
    # r2 at goal 2 twice, then at goal 1 twice: 1, 2, 1, 2 plans; never 3.
    out = _run(stage, scenario, [[-1, 2, -1], [-1, 2, -1], [-1, 1, -1], [-1, 1, -1]])
    assert out == [{}, {}, {}, {}]
    # Seen at the robot's own goal the count stops, so a team waiting with it is none.
    stage, scenario = _stage()
    out = _run(stage, scenario, [[-1, 2, -1], [-1, 2, -1], [-1, 0, -1], [-1, 0, -1]])
    assert out == [{}, {}, {}, {}]


def test_an_anchor_stays_one_when_the_robot_turns_to_its_goal():
    stage, scenario = _stage()
    _run(stage, scenario, [[-1, 2, -1]] * 3)
    stage._heading[0] = 2  # the robot now heads for the anchor's goal: it counts on
    assert stage.anchors(_seen(scenario, 3, [-1, 2, -1]), 0) == {1: 2}


def test_of_teammates_held_at_two_goals_the_one_seen_there_longest_wins():
    stage, scenario = _stage()
    # r3 settles at goal 1 from plan 0, r2 at goal 2 from plan 1: at plan 3 r3 has 4
    # plans, r2 3. Both pass the count; only r3's goal holds (groups in sight of each
    # other would otherwise hold each other, and no configuration holds both).
    out = _run(stage, scenario, [[-1, -1, 1], [-1, 2, 1], [-1, 2, 1], [-1, 2, 1]])
    assert out == [{}, {}, {2: 1}, {2: 1}]


@pytest.mark.parametrize(("kind", "settled"), [("allocation", 3), ("rendezvous", 0)])
def test_no_anchors_off_rendezvous_or_when_off(kind, settled):
    stage, scenario = _stage(kind, settled)
    assert _run(stage, scenario, [[-1, 2, -1]] * 4) == [{}, {}, {}, {}]


TABLE = np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2]])  # rendezvous of three at one of 3 goals


def _sets(own, pair, triple) -> NestedSets:
    own, pair, triple = (np.array(m, dtype=bool) for m in (own, pair, triple))
    return NestedSets(own, [pair], {1: pair, 2: pair}, {(1, 2): triple})


def test_held_to_keeps_each_set_s_part_at_the_anchor_or_the_anchor_s_rows():
    sets = _sets([False, True, False], [True, True, False], [False, False, False])
    held = held_to(sets, TABLE, {2: 0})  # r3 holds to goal 0
    # The own set (goal 1 only) has no row there: it becomes the rows with r3 at goal 0.
    assert held.own.tolist() == [True, False, False]
    # r2's set kept goals 0 and 1: its part at goal 0 stays. The empty triple (a chain
    # whose facts contradict, restricting nothing) is held there too.
    assert held.pairs[1].tolist() == [True, False, False]
    assert held.triples[(1, 2)].tolist() == [True, False, False]
    assert held.union.tolist() == [True, True, False]  # the table keeps the rest


def test_held_to_changes_nothing_without_a_common_goal():
    sets = _sets([False, True, False], [True, True, False], [True, True, True])
    assert held_to(sets, TABLE, {}) is sets
    assert held_to(sets, TABLE, {1: 0, 2: 2}) is sets  # two anchors at two goals


def test_plan_settled_is_a_count():
    assert ActiveParameters().plan_settled >= 0
    for bad in (-1, 2.5, True):
        with pytest.raises(EpistemicaError, match="plan_settled must be an integer >= 0"):
            ActiveParameters(plan_settled=bad)
