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
from epistemica.sim.policies.search import RendezvousSearch

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
    # Without the meeting, the search as it was before it: goals, then the sweep (with
    # ``plan_sighted`` r1 and r2 would chase their last sightings of r3 and r4 instead).
    parameters = mission.parameters.replace(plan_meet=meet, plan_sighted=meet)
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


# Three goals; r1 and r2 have met while searching. r2 knows only g2 and g3, and sees r1
# (the lowest-numbered robot in its sight: the leader) 4 m off, noisily, nearer g3 than g1.
MET = """\
mission rendezvous
workspace 30
robot r1: range at (5, 5)
robot r2: range at (12, 12)
goal g1 at (5, 5)
goal g2 at (25, 25)
goal g3 at (12, 5)
sensing model paper noise 0.5 range 10
event settle seen by nearby
"""


def _met(settles: np.ndarray, estimate=(10.0, 6.0)) -> tuple[RendezvousSearch, Observations]:
    scenario = parse_mission(MET).scenario(0)
    search = RendezvousSearch(scenario, 10.0, 15, 0.8, 2, meet=True)
    poses = np.zeros((2, 2, 3))
    poses[0, 0, :2], poses[1, 1, :2] = (5.0, 5.0), (12.0, 12.0)
    poses[1, 0, :2], poses[0, 1, :2] = estimate, (12.0, 12.0)
    known = np.array([[True, False, False], [False, True, True]])
    seen = np.ones((2, 2), dtype=bool)
    observations = Observations(9, poses, seen, np.full((2, 2), 9), known, ~known, None, settles)
    search.left[:] = [0, 1]  # both search, each from a goal of its own
    return search, observations


def _meet_once(search, observations):
    robots, seen = np.arange(2), observations.seen & ~np.eye(2, dtype=bool)
    own, still = np.array([0, -1]), np.array([True, False])
    return search._meet(observations, robots, own, still, seen, np.zeros((2, 2), dtype=bool))


def test_a_follower_steers_for_its_leader_until_it_sees_where_it_settles():
    search, observations = _met(np.full((2, 2), -1))  # r1 seen moving
    ended = _meet_once(search, observations)
    assert search.leader.tolist() == [0, 0]
    # r1 leads to the goal nearest its own position that it knows: g1, where it stands
    # still, so its search ends. r2 does not know g1: "the goal nearest the leader" it
    # could compute is g3 (nearest its noisy view of r1); it follows r1 instead.
    assert search.meeting.tolist() == [0, -1] and ended.tolist() == [True, False]
    assert np.allclose(search.target(observations, 1), (10.0, 6.0))
    settles = np.array([[-1, -1], [0, -1]])  # r2 sees r1 settle at g1
    search, observations = _met(settles)
    _meet_once(search, observations)
    assert search.meeting[1] == 0
    assert np.allclose(search.target(observations, 1), (5.0, 5.0))


def _roaming(settle_steps: list[int]) -> RendezvousSearch:
    """r1 waits at g1; r2 is seen there, settled at the ``settle_steps`` of 0-4 only."""
    search, _ = _met(np.full((2, 2), -1))
    search.left[:] = -1
    robots, travelling = np.array([0]), np.array([False])
    for step in range(5):
        settles = np.full((2, 2), -1)
        if step in settle_steps:
            settles[0, 1] = 0
        _, observations = _met(settles)
        search._roam(observations, robots, travelling)
    return search


def test_a_teammate_seen_to_leave_its_goal_is_no_anchor():
    # Seen settled at g1, then seen away from it: it searches, so it is no anchor.
    assert _roaming([0, 1, 3, 4]).roamed[0, 1]
    # Seen settled at every step, or only from when it arrived: it may never leave.
    assert not _roaming([0, 1, 2, 3, 4]).roamed[0, 1]
    assert not _roaming([2, 3, 4]).roamed[0, 1]
    # A robot that stands at no goal and searches no more forgets what it saw.
    search = _roaming([0, 2])
    _, observations = _met(np.full((2, 2), -1))
    search._roam(observations, np.array([0]), np.array([True]))
    assert not search.roamed[0, 1]
