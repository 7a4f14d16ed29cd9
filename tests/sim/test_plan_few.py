"""A teammate that knows too few goals is not predicted at a goal it was not shown
(``plan_few``, :func:`~epistemica.sim.policies.configuration_sets.known_slots`,
:meth:`~epistemica.sim.engine.knowledge.TeamKnowledge.unshown`): its empty set is held off
goals opened by an event it did not see, and, end to end, tuning mission asymmetry 2, where
the robot shown the new goal now takes it and leaves the old one to the teammate that knows
only that."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.aif.planning import Planner
from epistemica.del_.state import Observation
from epistemica.mission import parse_mission
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.worlds import goal_atoms
from epistemica.sim.policies.configuration_sets import NestedSets, known_slots
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import recording_plans

#: Allocations of two robots over three goals (scenario indices).
TABLE = np.array([[0, 1], [1, 0], [0, 2], [2, 0], [1, 2], [2, 1]])


def _sets(knowledge: TeamKnowledge, robot: int) -> NestedSets:
    teammate = 1 - robot
    pair = knowledge.possible((robot, teammate), TABLE)
    triple = knowledge.possible((robot, teammate, robot), TABLE)
    own = knowledge.possible((robot,), TABLE)
    return NestedSets(own, [pair], {teammate: pair}, {(teammate, robot): triple})


def _opens(knowledge: TeamKnowledge, goal: int, full: set[str]) -> None:
    """``goal`` opens and is revealed to ``full`` (as a mission event's ``reveals``)."""
    atoms = goal_atoms(knowledge.robots, knowledge.goals[goal])
    knowledge.observe(Observation("change", full=full, aware=atoms,
                                  withdraws=(knowledge.closed[goal],)))  # fmt: skip


def test_a_teammate_not_shown_an_opened_goal_is_held_off_it():
    # r1 was shown g1; r2 g1 and g2 (privately); g3 opens, revealed to r2 alone.
    knowledge = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"],
                              [[True, False, False], [True, True, False]])  # fmt: skip
    _opens(knowledge, 2, {"r2"})
    assert knowledge.unshown((1, 0)).tolist() == [False, False, True]
    sets = _sets(knowledge, 1)
    assert sets.own.tolist() == [True] * 6
    assert not sets.pairs[0].any()  # r1 conceives of no allocation: restricts nothing
    held = known_slots(sets, knowledge, 1, TABLE)
    # Rows with r1 (column 0) off g3; g2 stays: r1 may have been shown it too.
    assert held.pairs[0].tolist() == [True, True, True, False, True, False]
    # What r1 thinks r2 does: r1 did not see the event, so it knows of nothing unshown.
    assert held.triples[0, 1] is sets.triples[0, 1]
    assert held.own is sets.own
    # Seen within discovery range of g3, r1 may have discovered it: nothing held.
    near = np.zeros((2, 3), dtype=bool)
    near[0, 2] = True
    assert known_slots(sets, knowledge, 1, TABLE, near).pairs[0] is sets.pairs[0]
    assert known_slots(sets, knowledge, 1, TABLE, near[::-1]).pairs[0].tolist() == (
        held.pairs[0].tolist()
    )


def test_goals_private_from_the_start_or_shown_later_hold_nothing():
    # Private from the start (generated missions' knows lines): a teammate may have been
    # shown them too, so nothing says it was not.
    knowledge = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"],
                              [[True, False, False], [True, True, True]])  # fmt: skip
    sets = _sets(knowledge, 1)
    assert not sets.pairs[0].any()
    assert not knowledge.unshown((1, 0)).any()
    assert known_slots(sets, knowledge, 1, TABLE).pairs[0] is sets.pairs[0]
    # An opened goal the teammate has since been seen to learn (a discovery both saw).
    knowledge = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"],
                              [[True, False, False], [True, True, False]])  # fmt: skip
    _opens(knowledge, 2, {"r2"})
    knowledge.discover(2, np.ones(2, dtype=bool))
    assert not knowledge.unshown((1, 0)).any()


def test_a_teammate_that_knows_no_open_goal_is_left_alone():
    # r1 knew g1 only, and saw it close; g3 opens, shown to r2 alone. r1 sweeps and ends
    # where it finds the team (tuning asymmetry 121, a rendezvous, lost a trial with it held).
    knowledge = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"],
                              [[True, False, False], [True, True, False]])  # fmt: skip
    knowledge.notice_closed(0, np.ones(2, dtype=bool))
    _opens(knowledge, 2, {"r2"})
    assert knowledge.unshown((1, 0)).tolist() == [False, False, True]
    sets = _sets(knowledge, 1)
    assert not sets.pairs[0].any()
    assert known_slots(sets, knowledge, 1, TABLE).pairs[0] is sets.pairs[0]


def test_a_chain_with_configurations_is_left_alone():
    knowledge = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"],
                              [[True, True, False], [True, True, False]])  # fmt: skip
    _opens(knowledge, 2, {"r2"})
    sets = _sets(knowledge, 1)
    assert sets.pairs[0].tolist() == [True, True, False, False, False, False]
    assert known_slots(sets, knowledge, 1, TABLE).pairs[0] is sets.pairs[0]


def test_the_held_teammate_leaves_the_robot_the_goal_it_alone_knows():
    # Hand-worked: goals 10 m apart, unit speeds, temperature 1, so tau = 10 s. Robot 1
    # stands 1 m from goal 0; robot 0 is 5 m from it and keeps only the row (0, 1). As
    # predicted at order 1 its one option is goal 0 (probability 1), so robot 1 heading for
    # goal 1 forms the allocation surely at max(5, 9) = 9 s: G = 0.9; heading for goal 0
    # forms it with probability 0: its own 1 s, plus -ln(1e-12) = 27.63 nats.
    planner = Planner([[0.0, 0.0], [10.0, 0.0]], [[0, 1], [1, 0]], [1.0, 1.0], order=2,
                      temperature=1.0)  # fmt: skip
    at = [[5.0, 0.0], [1.0, 0.0]]
    held = planner.plan(1, at, sets={(1, 0): np.array([True, False])})
    assert held.goal == 1
    assert held.predictions[0].tolist() == [1.0, 0.0]
    assert held.G.tolist() == pytest.approx([0.1 - np.log(1e-12), 0.9], abs=1e-9)
    # An empty set restricts nothing: robot 0 is predicted on either goal, robot 1 stays.
    assert planner.plan(1, at, sets={(1, 0): np.zeros(2, bool)}).goal == 0


#: Tuning mission asymmetry 2 (generator seed 2), cut to its first 12 steps: at step 10
#: g1 closes under r1 and g4 opens, shown to r2 alone; r1 knows one open goal, g3.
MISSION = """mission allocation
workspace 36
robot r1: range at (29.2, 33.9)
robot r2: range at (17.6, 1.3)
goal g1 at (29.5, 33.9)
goal g2 at (4.7, 16.8)
goal g3 at (8.3, 15.6)
goal g4 at (12.7, 29.2) closed
sensing model honest noise 0.3 discovery 5 range 26
knows r1: g1, g3
knows r2: g1, g3
event settle seen by nearby
event change1 {
    when step 10
    closes g1
    opens g4
    announces closed(g1)
    reveals g4
    full r2
}
event change2 {
    when step 4
    closes g2
    announces closed(g2)
    full robots if near(g2, 10)
}
simulate trials 1 seed 0 steps 12 levels third
"""


@pytest.mark.parametrize(("few", "goal"), [("false", 2), ("true", 3)])
def test_mission_asymmetry_2_r2_takes_the_goal_only_it_was_shown(few, goal):
    mission = parse_mission(MISSION + f"policy plan_few {few}\n", "asymmetry_2.epi")
    with recording_plans() as plans:
        mission.trial(12, 0, "third")
    after = [p.chosen for p in plans if p.robot == 1 and p.step >= 10]
    assert len(after) == 2 and set(after) == {goal}  # g3 without the option, g4 with it


def test_on_by_default():
    assert ActiveParameters().plan_few is True
