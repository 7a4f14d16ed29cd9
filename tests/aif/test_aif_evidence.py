"""Evidence by sensor and reasoning order: hand-worked values, perspectives, invariances."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from epistemica.aif import (
    bearing_evidence,
    chain_counts,
    dominates,
    evidence_by_order,
    measurement_stack,
    measurements,
    perspective_sets,
    range_evidence,
)
from epistemica.del_.errors import InvalidArgumentError

GOALS = np.array([[2.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])


def test_range_evidence_hand_worked():
    assert range_evidence([[0.0, 0.0]], [[3.0, 4.0]], eta=5.0)[0, 0] == pytest.approx(np.exp(-1))


def test_bearing_evidence_hand_worked():
    # From the origin, a robot at (1, 0) is aligned with (2, 0), at a right angle to
    # (0, 1) and opposite to (-1, 0).
    e = bearing_evidence([0.0, 0.0], [[1.0, 0.0]], GOALS, eta_bearing=1.0)
    np.testing.assert_allclose(e[0], np.exp([0.0, -np.pi / 2, -np.pi]))


def test_bearing_undefined_angles_are_neutral():
    # Robot on the viewpoint: no direction at all; goal on the viewpoint: no direction.
    e = bearing_evidence([0.0, 0.0], [[0.0, 0.0], [1.0, 0.0]], [[0.0, 0.0], [2.0, 0.0]])
    np.testing.assert_allclose(e[0], np.exp(-np.pi / 2))
    assert e[1, 0] == pytest.approx(np.exp(-np.pi / 2))
    assert e[1, 1] == pytest.approx(1.0)


def test_dominance():
    assert dominates("range", "bearing") and not dominates("bearing", "range")
    assert dominates("range", "range") and dominates("bearing", "bearing")
    with pytest.raises(InvalidArgumentError, match="unknown sensor"):
        dominates("lidar", "range")


def test_perspective_sets_hand_worked():
    # 0 (range) takes 1 (bearing) and 2 (range); 1 cannot take 2; 2 takes 1.
    assert perspective_sets(["range", "bearing", "range"], 0, 3) == [
        [(0,)],
        [(0,)],
        [(0, 1), (0, 2)],
        [(0, 2, 1)],
    ]
    # A bearing robot takes only bearing robots' perspectives.
    assert perspective_sets(["bearing", "range", "bearing"], 0, 3) == [[(0,)], [(0,)], [(0, 2)], []]
    assert chain_counts(["range"] * 3, 1, 3).tolist() == [
        [0, 1, 0],
        [0, 1, 0],
        [1, 0, 1],
        [1, 0, 1],
    ]


def _scene():
    positions = np.array([[0.0, 0.0], [4.0, 1.0], [1.0, 5.0]])
    goals = np.array([[6.0, 2.0], [-3.0, 4.0]])
    return positions, goals


def test_orders_hand_worked():
    positions, goals = _scene()
    sensors = ["range", "bearing", "range"]
    e = evidence_by_order(0, positions, goals, sensors, 3, eta=10.0, eta_bearing=1.0)
    m = {v: measurements(v, positions, goals, sensors, 10.0, 1.0) for v in range(3)}
    own = np.zeros((3, 2))
    own[0] = np.exp(-np.hypot(*(positions[0] - goals).T) / 10.0)
    np.testing.assert_allclose(e[0], own)
    np.testing.assert_allclose(e[1], m[0])
    np.testing.assert_allclose(e[2], m[1] + m[2])
    # Order 3 is the single nested chain (0, 2, 1): what range robot 2 reconstructs of
    # bearing robot 1's view. (0, 1, 2) is not a chain: bearing 1 cannot emulate range 2.
    np.testing.assert_allclose(e[3], m[1])
    assert not np.allclose(e[3], e[2])
    # Own row: order 0 only; measurements never speak about the measuring robot itself.
    assert np.all(e[1, 0] == 0)
    assert np.all(m[1][1] == 0)


def test_bearing_measurement_matches_geometry():
    positions, goals = _scene()
    m1 = measurements(1, positions, goals, ["range", "bearing", "range"], 10.0, 1.0)
    v = positions[1]
    for r in (0, 2):
        for g in range(2):
            a, b = positions[r] - v, goals[g] - v
            angle = np.arccos(a @ b / np.linalg.norm(a) / np.linalg.norm(b))
            assert m1[r, g] == pytest.approx(np.exp(-angle))


def test_measurement_stack_batches_measurements():
    positions, goals = _scene()
    sensors = ["range", "bearing", "bearing"]
    stack = measurement_stack(np.stack([positions, positions + 1.0]), goals, sensors)
    for v in range(3):
        np.testing.assert_allclose(stack[0, v], measurements(v, positions, goals, sensors))
        np.testing.assert_allclose(stack[1, v], measurements(v, positions + 1.0, goals, sensors))


@settings(max_examples=30, deadline=None)
@given(
    arrays(float, (3, 2), elements=st.floats(-50, 50)),
    arrays(float, (2, 2), elements=st.floats(-50, 50)),
    st.floats(-np.pi, np.pi),
    arrays(float, 2, elements=st.floats(-100, 100)),
    st.lists(st.sampled_from(["range", "bearing"]), min_size=3, max_size=3),
    st.integers(0, 3),
)
def test_evidence_invariant_under_rigid_motion(pos, goals, angle, shift, sensors, order):
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    e1 = evidence_by_order(0, pos, goals, sensors, order)
    e2 = evidence_by_order(0, pos @ rot.T + shift, goals @ rot.T + shift, sensors, order)
    assert np.all(np.isfinite(e1)) and np.all(e1 >= 0)
    # Near-coincident points may flip between "undefined" and a defined angle; skip those.
    d = np.hypot(*(pos[:, None] - np.concatenate([pos, goals])[None]).transpose(2, 0, 1))
    np.fill_diagonal(d[:, :3], np.inf)
    if d.min() > 1e-3:
        np.testing.assert_allclose(e1, e2, atol=1e-7)


def test_bad_inputs_raise_with_hint():
    with pytest.raises(InvalidArgumentError, match="NaN") as err:
        range_evidence([[np.nan, 0.0]], GOALS)
    assert err.value.hint
    with pytest.raises(InvalidArgumentError, match="sensors for"):
        evidence_by_order(0, [[0, 0], [1, 1]], GOALS, ["range"], 1)
    with pytest.raises(InvalidArgumentError, match="order must be"):
        evidence_by_order(0, [[0, 0]], GOALS, ["range"], 4)
    with pytest.raises(InvalidArgumentError, match="robot must be"):
        evidence_by_order(3, [[0, 0]], GOALS, ["range"], 1)
    with pytest.raises(InvalidArgumentError, match="x and y"):
        range_evidence([[0.0]], GOALS)
