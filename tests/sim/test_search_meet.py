"""The planner levels' end of a rendezvous search (``plan_meet``): a searcher that sees
teammates outside the group it left with has found them."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.del_.errors import EpistemicaError
from epistemica.mission import parse_mission
from epistemica.sim import Scenario, simulate
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage

# Two pairs 28 m apart, out of sight (10 m). Both know both goals; r3 and r4 set off for
# g1 (the planner's convention), while r1 and r2 wait at g1 unseen and, after their wait,
# go looking for the rest and cross r3 and r4 on the diagonal before either pair settles.
SPLIT = """\
mission rendezvous
workspace 30
robot r1: range at (5, 6)
robot r2: range at (6, 5)
robot r3: range at (25, 24)
robot r4: range at (24, 25)
goal g1 at (5, 5)
goal g2 at (25, 25)
sensing model paper noise 0.5 range 10
event settle seen by nearby
simulate trials 1 seed 0 steps 120 levels third
"""


def _trial(level: str, meet: bool):
    mission = parse_mission(SPLIT)
    parameters = mission.parameters.replace(plan_meet=meet)
    return simulate(mission.scenario(0), level, seed=0, parameters=parameters)


def _from_g1(trial, robot: int) -> np.ndarray:
    return np.hypot(*(trial.trajectory[:, robot, :2] - [5.0, 5.0]).T)


def test_searchers_that_see_the_rest_of_the_team_turn_back_to_meet_it():
    met, searched = _trial("third", True), _trial("third", False)
    assert ActiveParameters().plan_meet
    # Without the rule r1 and r2 pass r3 and r4 (unsettled, so not "found") and sweep on:
    # r1 reaches the far corner before the team meets.
    assert searched.success and _from_g1(searched, 0).max() > 20.0
    # With it, r1 sees r3 and r4 within 10 m of g1 and all four head for the goal nearest
    # r1 (the lowest-numbered robot in sight): g1, where r3 and r4 were going anyway.
    assert met.success and met.steps < searched.steps - 40
    assert _from_g1(met, 0).max() < 10.0
    assert (_from_g1(met, 0)[:15] < 1.5).all()  # r1 waited at g1 before it searched
    final = met.trajectory[-1, :, :2]
    assert (np.hypot(*(final - [5.0, 5.0]).T) < 1.0).all()


def test_the_rules_levels_never_meet():
    on, off = _trial("rules-third", True), _trial("rules-third", False)
    assert np.array_equal(on.trajectory, off.trajectory)
    assert _from_g1(on, 0).max() > 20.0  # r1 sweeps past r3 and r4 as before


def test_plan_meet_is_a_switch():
    with pytest.raises(EpistemicaError, match="plan_meet must be true or false"):
        ActiveParameters(plan_meet=1)


def _observations(step: int, teammate) -> Observations:
    poses = np.zeros((2, 2, 3))
    poses[:, 0, :2] = [5.0, 5.0]
    poses[:, 1, :2] = teammate
    seen = np.ones((2, 2), dtype=bool)
    last = np.full((2, 2), step)
    known = np.ones((2, 2), dtype=bool)
    return Observations(step, poses, seen, last, known, ~known)


def test_a_robot_whose_search_ended_reads_no_moves_across_it():
    stage = PlanningStage(Scenario.paper("rendezvous", 2, 2, seed=3), ActiveParameters(), 2)
    stage.observe(_observations(4, [15.0, 15.0]), 0)
    # The teammate stood still: it used none of its speed, seen in both sightings.
    assert stage.observe(_observations(5, [15.0, 15.0]), 0)[1] == 0.0
    stage.forget(0)
    # Forgotten: no earlier sighting to compare with, so nothing is read (1: cannot tell).
    assert stage.observe(_observations(6, [15.0, 15.0]), 0).tolist() == [1.0, 1.0]
    assert stage.observe(_observations(7, [15.0, 15.0]), 0)[1] == 0.0
