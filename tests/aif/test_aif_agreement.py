"""Robots with the same information hold the same belief, at every order of reasoning.

Range robots measure the same distances whoever looks, so with shared, noiseless
positions no robot knows more than another: their beliefs must coincide. Counting a
robot's own row once per chain that measures it (the bug this guards against) made each
robot trust its own nearest goal most, and two robots then claimed the same goal.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from epistemica.aif import Controller, valid_configurations
from epistemica.aif.perspective import perspectives, row_weights


@given(
    n=st.integers(2, 4),
    order=st.integers(1, 3),
    mission=st.sampled_from(["allocation", "rendezvous"]),
    seed=st.integers(0, 2**32 - 1),
)
def test_same_information_same_belief(n, order, mission, seed):
    rng = np.random.default_rng(seed)
    goals = rng.uniform(0, 30, (n, 2))
    poses = rng.uniform(0, 30, (n, 2))
    ctrl = Controller(goals, ["range"] * n, valid_configurations(mission, n, n), order=order)
    beliefs = [ctrl.beliefs(i, poses)[0] for i in range(n)]
    for q in beliefs[1:]:
        np.testing.assert_allclose(q, beliefs[0], rtol=1e-12, atol=1e-15)


def test_two_range_robots_agree_on_allocation():
    # Each robot nearer a different goal, everything symmetric but the distances.
    goals = [[10.0, 0.0], [-10.0, 0.0]]
    poses = [[3.0, 1.0], [-4.0, -2.0]]
    ctrl = Controller(goals, ["range", "range"], valid_configurations("allocation", 2, 2), order=2)
    (q0, f0), (q1, f1) = ctrl.beliefs(0, poses), ctrl.beliefs(1, poses)
    assert f0 == f1 == 0  # both: robot 0 to goal 0 (the nearer one for each)
    np.testing.assert_allclose(q0, q1)


@given(st.lists(st.sampled_from(["range", "bearing"]), min_size=2, max_size=5), st.data())
def test_every_row_weight_counts_its_terms(sensors, data):
    robot = data.draw(st.integers(0, len(sensors) - 1))
    order = data.draw(st.integers(0, 3))
    for view, weights in zip(
        perspectives(sensors, robot, order),
        row_weights(perspectives(sensors, robot, order), len(sensors)),
        strict=True,
    ):
        terms = view.counts.sum() - view.counts + (np.arange(len(sensors)) == view.agent)
        assert np.array_equal(weights, np.maximum(terms, 1))


@given(
    seed=st.integers(0, 2**32 - 1),
    noise=st.floats(0.1, 64.0),
    order=st.integers(1, 3),
    sensors=st.lists(st.sampled_from(["range", "bearing"]), min_size=2, max_size=4),
)
def test_more_observation_noise_means_less_confident_beliefs(seed, noise, order, sensors):
    """Attenuated evidence: each robot's goal distribution moves towards uniform (its KL
    from uniform shrinks) as the stated noise grows; zero noise changes nothing."""
    from epistemica.aif import entropy

    n = len(sensors)
    rng = np.random.default_rng(seed)
    goals, poses = rng.uniform(0, 30, (n, 2)), rng.uniform(0, 30, (n, 2))
    rows = valid_configurations("all", n, 2)
    exact = Controller(goals[:2], sensors, rows, order=order)
    noisy = Controller(goals[:2], sensors, rows, order=order, position_noise=noise)
    noisier = Controller(goals[:2], sensors, rows, order=order, position_noise=4 * noise)
    for robot in range(n):
        q = [c.beliefs(robot, poses)[0] for c in (exact, noisy, noisier)]
        h = [entropy(x) for x in q]  # "all" rows: independent robots, entropy adds up
        assert h[0] <= h[1] + 1e-12 <= h[2] + 2e-12
    zero = Controller(goals[:2], sensors, rows, order=order, position_noise=0.0)
    assert np.array_equal(zero.beliefs(0, poses)[0], exact.beliefs(0, poses)[0])
