"""What a trace keeps of knowledge: who knows which goal (and who takes whom to know it),
closed goals, obstacles; and the focus robot chosen from it."""

from __future__ import annotations

import numpy as np

from epistemica.sim import Scenario, simulate
from epistemica.sim.study.palette import focus_robot
from epistemica.sim.study.trace import decode, encode, known_goals, trial_trace

STARTS = [[2.0, 2.0], [28.0, 2.0], [2.0, 28.0]]
GOALS = [[5.0, 25.0], [25.0, 25.0], [15.0, 15.0]]


def _private(**changes) -> Scenario:
    """r2 alone knows of g3 (the others know g1 and g2); discovery within 1 m."""
    known = np.array([[True, True, False], [True, True, True], [True, True, False]])
    return Scenario(
        "rendezvous", STARTS, GOALS, ["range"] * 3, workspace=30.0, known_goals=known,
        discovery_range=1.0, max_steps=8, **changes,
    )  # fmt: skip


def test_knows_lists_the_start_and_round_trips_to_the_trials_array():
    s = _private()
    trial = simulate(s, "rules-first", seed=1)
    trace = decode(encode(trial_trace(s, trial)))
    start = {(i, j, g) for step, i, j, g, now, how in trace["knows"] if step == 0}
    # Own knowledge at the start: the told goals; another's: the goals every robot knows.
    own = {(i, i, g) for i in range(3) for g in range(3) if g < 2 or i == 1}
    common = {(i, j, g) for i in range(3) for j in range(3) for g in range(2) if i != j}
    assert start == own | common
    assert {how for step, *_, how in trace["knows"] if step == 0} == {"start"}
    assert np.array_equal(known_goals(trace), trial.known_goals)
    # r2 alone knows of a goal it takes the others not to know of: the focus robot.
    assert focus_robot(trace) == 1


def test_common_knowledge_keeps_no_knows_field():
    s = Scenario("rendezvous", STARTS, GOALS, ["range"] * 3, workspace=30.0, max_steps=3)
    trace = trial_trace(s, simulate(s, "rules-first", seed=0))
    assert "knows" not in trace and known_goals(trace) is None
    assert "closed" not in trace and "obstacles" not in trace


def test_closed_goals_and_obstacles_are_in_the_trace():
    square = [[10.0, 5.0], [12.0, 5.0], [12.0, 7.0], [10.0, 7.0]]
    s = _private(closed=[False, True, False], obstacles=[square])
    trace = trial_trace(s, simulate(s, "rules-first", seed=0))
    assert trace["closed"][0] == [0, 1, 1]
    assert trace["obstacles"] == [square]
    assert trace["discovery_range"] == 1.0
