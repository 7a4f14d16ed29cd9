"""The planner's teammate types: a teammate read as holding to its goal is predicted there.

Hand-worked: a teammate that stands on a goal while the planner predicts it to leave
for another is typed once the posterior, computed here from the Gaussian densities
written out, reaches the threshold; the planner then keeps only the configurations with
it on that goal. A teammate that moves as the planner predicts is never typed, and the
plan is the one without types, bit for bit.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from epistemica.aif.planning import Planner
from epistemica.aif.teammates import (
    TYPE_PRIOR,
    TYPES,
    motion_log_likelihood,
    planner_type_goals,
    typed_predictions,
    update_types,
)
from epistemica.del_.errors import EpistemicaError

GOALS = np.array([[0.0, 0.0], [20.0, 0.0]])
SIGMA, REACH, THRESHOLD = 1.0, 1.0, 0.97


def _density(x, mean) -> float:
    """The isotropic 2-D normal density of ``x`` around ``mean`` (``SIGMA``)."""
    d2 = float(((np.asarray(x) - np.asarray(mean)) ** 2).sum())
    return np.exp(-d2 / (2 * SIGMA**2)) / (2 * np.pi * SIGMA**2)


def _read(positions, planned, convention) -> np.ndarray:
    """Log type posterior after the one-teammate walk ``positions`` (leak 0)."""
    log_types = np.log(TYPE_PRIOR)[None]
    for before, after in itertools.pairwise(positions):
        distance = np.hypot(*(GOALS - before).T)[None]
        probs = planner_type_goals(planned, distance, convention)
        ll = motion_log_likelihood(before[None], after[None], probs, GOALS,
                                   np.array([REACH]), SIGMA)  # fmt: skip
        log_types = update_types(log_types, ll, leak=0.0)
    return log_types


def test_a_teammate_standing_on_a_goal_it_is_predicted_to_leave_is_typed_by_hand():
    # The planner predicts the teammate heading for goal 0; it stands on goal 1 (its
    # nearest). Per step: greedy and stationary predict it where it is, the team and the
    # other convention (goal 0 here) one step towards goal 0.
    planned = np.array([[1.0, 0.0]])
    floor = 1e-4
    still = _density([20.0, 0.0], [20.0, 0.0])
    leave = _density([20.0, 0.0], [19.0, 0.0])
    per_step = {
        "team": leave,
        "greedy": (1 - floor) * still + floor * leave,
        "convention": (1 - floor) * leave + floor * still,
        "stationary": still,
    }
    typed_at = []
    for k in range(1, 16):
        log_types = _read(np.tile(GOALS[1], (k + 1, 1)), planned, np.array([0]))
        joint = np.array([TYPE_PRIOR[TYPES.index(t)] * per_step[t] ** k for t in TYPES])
        expected = joint / joint.sum()
        assert np.allclose(np.exp(log_types[0]), expected, rtol=1e-9)
        holding = expected[TYPES.index("greedy")] + expected[TYPES.index("stationary")]
        probs = planner_type_goals(planned, np.array([[20.0, 0.0]]), np.array([0]))
        row = typed_predictions(log_types, probs, THRESHOLD)[0]
        assert np.isnan(row).all() == (holding < THRESHOLD)
        if holding >= THRESHOLD:
            typed_at.append(k)
            assert row.argmax() == 1 and row[1] > 0.999  # at the goal it stands on
    assert typed_at and typed_at[0] > 1  # not at once: it takes standing for a while
    assert typed_at == list(range(typed_at[0], 16))


def test_a_teammate_moving_as_the_planner_predicts_is_never_typed():
    # It walks from (15, 0) towards goal 0, as predicted; its nearest goal is goal 1.
    walk = np.array([[15.0 - step, 0.0] for step in range(12)])
    log_types = _read(walk, np.array([[1.0, 0.0]]), np.array([1]))
    assert TYPES[int(np.argmax(log_types[0]))] == "team"
    distance = np.hypot(*(GOALS - walk[-1]).T)[None]
    probs = planner_type_goals(np.array([[1.0, 0.0]]), distance, np.array([1]))
    assert np.isnan(typed_predictions(log_types, probs, THRESHOLD)).all()


def _rendezvous_planner() -> tuple[Planner, np.ndarray, np.ndarray]:
    """Three robots; robots 0 and 1 stand on goal 0 (teammate 1 read as heading there),
    teammate 2 stands on goal 1."""
    planner = Planner(GOALS, [[0, 0, 0], [1, 1, 1]], [1.0, 1.0, 1.0], order=3)
    positions = np.array([[0.5, 0.0], [0.0, 0.5], [20.0, 0.0]])
    evidence = np.zeros((3, 2))
    evidence[1] = [0.0, -30.0]
    return planner, positions, evidence


def test_the_planner_predicts_a_typed_teammate_on_its_goal_in_every_chain():
    planner, positions, evidence = _rendezvous_planner()
    plain = planner.plan(0, positions, evidence=evidence)
    assert plain.goal == 0  # as a planner, teammate 2 is predicted to join the two
    assert plain.predictions[2].argmax() == 0
    typed = np.full((3, 2), np.nan)
    typed[2] = [1e-4, 1 - 1e-4]
    result = planner.plan(0, positions, evidence=evidence, typed=typed)
    assert result.goal == 1  # it will not come: the team goes to it
    assert result.predictions[2].argmax() == 1
    assert result.belief[0] == 0.0 and result.belief[1] == 1.0  # only c_2 = goal 1 kept
    # Teammate 1, predicted by the planner one order down, now goes there too: the
    # chain (0, 1, 2) reads the type.
    assert result.predictions[1].argmax() == 1
    # What it would do as a planner is kept apart (its moves are scored against it).
    assert np.allclose(result.planned[2], plain.predictions[2])


def test_no_typed_row_plays_the_plan_without_types_bit_for_bit():
    planner, positions, evidence = _rendezvous_planner()
    plain = planner.plan(0, positions, evidence=evidence)
    none = planner.plan(0, positions, evidence=evidence, typed=np.full((3, 2), np.nan))
    assert none.goal == plain.goal
    for a, b in zip(none[1:5], plain[1:5], strict=True):
        assert np.array_equal(a, b)


@pytest.mark.parametrize(
    "typed", [np.zeros((2, 2)), np.full((3, 3), np.nan), [[np.nan] * 2, [-1.0, 2.0], [0, 1]]]
)
def test_bad_typed_rows_are_refused(typed):
    planner, positions, _ = _rendezvous_planner()
    with pytest.raises(EpistemicaError):
        planner.plan(0, positions, typed=typed)
