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
