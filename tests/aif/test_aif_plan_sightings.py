"""Sightings read by a filter per goal hypothesis (``filter_sightings``, ``plan_filter``):
hand-worked Kalman steps, and the exact-sighting case against ``motion_evidence``."""

import numpy as np
import pytest

from epistemica.aif.planning import filter_sightings, motion_evidence
from epistemica.sim import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage

GOALS = [[10.0, 0.0], [-10.0, 0.0]]


def _track(n: int = 1, m: int = 2) -> tuple:
    return np.zeros((n, m, 2)), np.zeros(n), np.full(n, -1)


def test_two_filter_steps_by_hand():
    # Sighting variance 1 m², model error 0.5 m per step, unit speed; sighted at x = 0, 1, 2.
    track = _track()
    assert filter_sightings(track, [[0.0, 0.0]], [1.0], GOALS, [1.0], 0, 0.5).tolist() == [
        [0.0, 0.0]
    ]
    # Step 1: predicted x = +1 (goal 0) or -1 (goal 1); prior 1 + 0.25, innovation S 2.25.
    first = filter_sightings(track, [[1.0, 0.0]], [1.0], GOALS, [1.0], 1, 0.5)
    assert first[0] == pytest.approx([0.0, -(2.0**2) / (2 * 2.25)])
    # Step 2. Goal 0: the estimate stays on the sightings (x = 1, then predicted 2).
    # Goal 1: the estimate was -1 + (1.25 / 2.25) * 2, then predicted one metre left.
    prior = 1.25 * (1 - 1.25 / 2.25) + 0.25
    estimate = -1.0 + 1.25 / 2.25 * 2.0 - 1.0
    second = filter_sightings(track, [[2.0, 0.0]], [1.0], GOALS, [1.0], 2, 0.5)
    S = prior + 1.0
    assert second[0] == pytest.approx([0.0, -((2.0 - estimate) ** 2) / (2 * S)])
    assert track[1][0] == pytest.approx(prior * (1 - prior / S))
    assert track[2].tolist() == [2]


def test_exact_sightings_read_what_motion_evidence_reads():
    rng = np.random.default_rng(7)
    goals = rng.uniform(-10, 10, (4, 2))
    track = _track(3, 4)
    before = rng.uniform(-5, 5, (3, 2))
    filter_sightings(track, before, np.zeros(3), goals, [1.0, 0.5, 2.0], 4, 0.3)
    after = before + rng.normal(0, 1, (3, 2))
    read = filter_sightings(track, after, np.zeros(3), goals, [1.0, 0.5, 2.0], 5, 0.3)
    expected = motion_evidence(before, after, goals, [1.0, 0.5, 2.0], 1.0, 0.3)
    np.testing.assert_allclose(read, expected)


def test_a_gap_widens_the_prior_and_the_reach_and_unsighted_rows_read_nothing():
    track = _track(2)
    filter_sightings(track, [[0.0, 0.0], [5.0, 5.0]], [1.0, 1.0], GOALS, [1.0, 1.0], 0, 0.5)
    # Robot 0 is sighted again three steps later, robot 1 is not.
    read = filter_sightings(track, [[3.0, 0.0], [np.nan, np.nan]], [1.0, 1.0], GOALS,
                            [1.0, 1.0], 3, 0.5)  # fmt: skip
    S = 1.0 + 3 * 0.25 + 1.0
    assert read[0] == pytest.approx([0.0, -(6.0**2) / (2 * S)])
    assert read[1].tolist() == [0.0, 0.0]
    assert track[2].tolist() == [3, 0]


def test_the_stage_reads_its_teammates_sightings_through_the_filter():
    scenario = Scenario.paper("rendezvous", 2, 2, seed=3).replace(position_noise=2.0)
    params = ActiveParameters(planning=True, plan_leak=0.0, plan_filter=True)
    stage = PlanningStage(scenario, params, order=2)
    poses = np.zeros((2, 2, 3))
    for step, x in ((4, 10.0), (5, 11.0)):
        poses[0, 0, :2], poses[0, 1, :2] = [5.0, 5.0], [x, 10.0]
        seen = np.ones((2, 2), dtype=bool)
        known = np.ones((2, 2), dtype=bool)
        stage.observe(Observations(step, poses.copy(), seen, np.full((2, 2), step), known,
                                   ~known), 0)  # fmt: skip
    # The paper sensor's variance is position_noise (2 m²) at any distance.
    track = _track(1, scenario.n_goals)
    speed = scenario.max_speed[[1]] * scenario.dt
    sigma = 0.5 * float(scenario.max_speed.mean()) * scenario.dt
    filter_sightings(track, [[10.0, 10.0]], [2.0], scenario.goals, speed, 4, sigma)
    expected = filter_sightings(track, [[11.0, 10.0]], [2.0], scenario.goals, speed, 5, sigma)
    np.testing.assert_allclose(stage._read[0][1], expected[0])
