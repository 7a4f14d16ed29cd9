"""``plan_hidden``: where a teammate never seen can be (``HiddenPlaces``), and the planner's
trips of such a teammate averaged over its draws (``Planner(arrivals=True)``)."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.aif.planning import Planner
from epistemica.del_.errors import EpistemicaError
from epistemica.sim import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.hidden_places import HiddenPlaces
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage

NEVER = np.array([False, True])  # robot 0 has never seen robot 1


def _scenario(**changes) -> Scenario:
    """Two robots at 1 m/s, steps of 1 s, goals at (2, 0) and (28, 0), sight 10 m."""
    goals = np.array([[2.0, 0.0], [28.0, 0.0]])
    scenario = Scenario.paper("allocation", 2, 2, seed=0)
    return scenario.replace(
        goals=goals, sensing_range=10.0, max_speed=np.ones(2), dt=1.0, **changes
    )


def test_a_hypothesis_is_ruled_out_once_its_place_falls_in_sight():
    # Starts A = (20, 0) and B = (0, 25); robot 0 stands at the origin and looks each step.
    # A -> g0 is at (20 - t, 0): within 10 m from t = 10. B -> g0 is at B + t u, with
    # |B + t u|^2 = 625 - 2 t 625 / |g0 - B| + t^2 = 100 at t = 15.12. A -> g1, B -> g1
    # (closest 18.6 m) and standing at A or B stay out of sight.
    places = HiddenPlaces(_scenario(), 16, starts=np.array([[20.0, 0.0], [0.0, 25.0]]))
    for step in range(10):
        places.sample(0, np.zeros(2), NEVER, step, np.array([0, 1]), tau=1e9)
    assert places.alive[0][1].tolist() == [[True, True, True], [True, True, True]]
    places.sample(0, np.zeros(2), NEVER, 10, np.array([0, 1]), tau=1e9)
    assert places.alive[0][1].tolist() == [[False, True, True], [True, True, True]]
    for step in range(11, 16):
        places.sample(0, np.zeros(2), NEVER, step, np.array([0, 1]), tau=1e9)
    assert places.alive[0][1][1].tolist() == [True, True, True]  # 15 < 15.12
    places.sample(0, np.zeros(2), NEVER, 16, np.array([0, 1]), tau=1e9)
    assert places.alive[0][1].tolist() == [[False, True, True], [False, True, True]]


def test_draws_are_the_hypotheses_left_moved_on_by_the_steps_elapsed():
    places = HiddenPlaces(_scenario(), 16, starts=np.array([[20.0, 0.0], [0.0, 25.0]]))
    for step in range(13):
        draws = places.sample(0, np.zeros(2), NEVER, step, np.array([0, 1]), tau=1e9)
    assert np.isnan(draws[:, 0]).all()
    # With tau large each start heads for either goal with 1/2 (and stands with 0.05):
    # weights A: (0, 0.5, 0.05), B: (0.5, 0.5, 0.05) of 1.6; 16 draws at (d + 1/2) / 16.
    unit = np.array([2.0, -25.0]) / np.hypot(2.0, 25.0)
    b_to_g0 = np.array([0.0, 25.0]) + 12 * unit
    b_to_g1 = np.array([0.0, 25.0]) + 12 * np.array([28.0, -25.0]) / np.hypot(28.0, 25.0)
    expected = {(28.0, 0.0): 5, (20.0, 0.0): 1, tuple(b_to_g0.round(6)): 5}
    expected[tuple(b_to_g1.round(6))] = 5
    found, counts = np.unique(draws[:, 1].round(6), axis=0, return_counts=True)
    assert dict(zip(map(tuple, found), counts.tolist(), strict=True)) == expected
    assert (np.hypot(*draws[:, 1].T) > 10.0).all()


def test_a_wall_hides_what_is_behind_it():
    wall = np.array([[4.0, -5.0], [5.0, -5.0], [5.0, 5.0], [4.0, 5.0]])
    places = HiddenPlaces(_scenario(obstacles=(wall,)), 4, starts=np.array([[8.0, 0.0], [0, 8.0]]))
    places.sample(0, np.zeros(2), NEVER, 0, np.array([0, 1]), tau=1e9)
    # Both starts are 8 m away; (8, 0) is behind the wall, (0, 8) in the open.
    assert places.alive[0][1][:, 2].tolist() == [True, False]


def test_planner_trips_of_a_hidden_teammate_come_from_its_draws():
    # Goals (0, 0) and (10, 0): spread 10 m, tau = 0.25 * 10 = 2.5 s, eta = 5 * 10 = 50 m.
    # Robot 0 stands on goal 0; robot 1, never seen, is placed at (5, 0) and drawn on
    # goal 1, so at order 0 it takes goal 1 with 1 / (1 + e^-0.2) = 0.5498.
    # G(0) = E[T | 0] / tau - ln 0.5498, with T = robot 1's trip to goal 1: 5 s from the
    # placeholder (2.598 nats), 0 s from the draw (0.598). G(1) = 10 / 2.5 - ln 0.4502 =
    # 4.798 either way (robot 0's own 10 s trip is the longest).
    draws = np.array([[[np.nan, np.nan], [10.0, 0.0]]])
    p1 = 1.0 / (1.0 + np.exp(-0.2))
    for arrivals, trip in ((False, 5.0), (True, 0.0)):
        planner = Planner([[0.0, 0.0], [10.0, 0.0]], [[0, 1], [1, 0]], [1.0, 1.0], order=1,
                          arrivals=arrivals)  # fmt: skip
        result = planner.plan(0, [[0.0, 0.0], [5.0, 0.0]], unseen=draws)
        expected = [trip / 2.5 - np.log(p1), 10.0 / 2.5 - np.log(1.0 - p1)]
        np.testing.assert_allclose(result.G, expected, rtol=1e-9)


def test_stage_hands_the_planner_draws_out_of_sight_and_checks_the_parameter():
    with pytest.raises(EpistemicaError):
        ActiveParameters(plan_hidden=-1)
    assert ActiveParameters().plan_hidden == 0  # off: no gain measured (aif.md §6g)
    scenario = _scenario()
    stage = PlanningStage(scenario, ActiveParameters(planning=True, plan_hidden=8), order=2)
    poses = np.zeros((2, 2, 3))
    poses[0, 1, :2] = scenario.workspace / 2  # the placeholder
    last = np.array([[0, -1], [0, 0]])
    known = np.ones((2, 2), dtype=bool)
    observations = Observations(0, poses, last == 0, last, known, ~known)
    draws = stage.unseen(observations, 0, np.array([0, 1]), 2.5)
    assert draws.shape == (8, 2, 2) and np.isnan(draws[:, 0]).all()
    assert (np.hypot(*draws[:, 1].T) > 10.0).all()
    off = PlanningStage(scenario, ActiveParameters(planning=True), order=2)
    assert off.unseen(observations, 0, np.array([0, 1]), 2.5) is None
    assert stage.options["arrivals"] and not off.options["arrivals"]
