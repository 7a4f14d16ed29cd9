"""Degenerate and extreme inputs: finite results or a clear InvalidArgumentError."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from epistemica.aif import (
    Controller,
    bayes_update,
    evidence_by_order,
    expected_free_energy,
    goal_log_probabilities,
    log_likelihood,
    policy_posterior,
    select_policy,
    valid_configurations,
    variational_free_energy,
)
from epistemica.del_.errors import EpistemicaError, InvalidArgumentError

SENSOR_MIXES = [["range"] * 3, ["bearing"] * 3, ["range", "bearing", "bearing"]]


def _finite_decision(ctrl, robot, poses, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no silent overflow, 0/0 or log(0)
        d = ctrl.decide(robot, poses, **kwargs)
    assert np.all(np.isfinite(d.G)) and np.all(np.isfinite(d.q_pi))
    assert np.all(np.isfinite(d.belief)) and d.belief.sum() == pytest.approx(1.0)
    return d


@pytest.mark.parametrize("sensors", SENSOR_MIXES)
@pytest.mark.parametrize("order", [0, 1, 2, 3])
def test_everything_coincident(sensors, order):
    # atan2(0, 0) everywhere: robots on each other and on the goals.
    goals = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]
    ctrl = Controller(goals, sensors, valid_configurations("allocation", 3, 3), order=order)
    for robot in range(3):
        _finite_decision(ctrl, robot, np.zeros((3, 3)))


@pytest.mark.parametrize("sensors", SENSOR_MIXES)
@pytest.mark.parametrize("horizon", [1, 2])
def test_distances_up_to_a_million_metres(sensors, horizon):
    goals = [[1e6, 0.0], [-1e6, 1e6], [0.0, -1e6]]
    poses = [[-1e6, -1e6, 0.0], [1e6, 1e6, 1.0], [0.0, 0.0, 2.0]]
    ctrl = Controller(
        goals, sensors, valid_configurations("allocation", 3, 3), order=3, horizon=horizon
    )
    _finite_decision(ctrl, 2, poses)


@settings(max_examples=20, deadline=None)
@given(
    arrays(float, (3, 2), elements=st.floats(-1e6, 1e6)),
    arrays(float, (2, 2), elements=st.floats(-1e6, 1e6)),
    st.lists(st.sampled_from(["range", "bearing"]), min_size=3, max_size=3),
)
def test_random_extreme_scenes_stay_finite(pos, goals, sensors):
    ctrl = Controller(
        goals, sensors, valid_configurations("capacity", 3, 2, capacities=[1, 2]), order=3
    )
    _finite_decision(ctrl, 0, np.column_stack([pos, np.zeros(3)]))
    e = evidence_by_order(1, pos, goals, sensors, 3)
    assert np.all(np.isfinite(e))
    L = log_likelihood(goal_log_probabilities(e), ctrl.configurations)
    assert np.all(np.isfinite(L))


def test_single_valid_configuration():
    ctrl = Controller(
        [[0.0, 0.0], [5.0, 5.0]],
        ["range", "bearing"],
        valid_configurations("capacity", 2, 2, capacities=[2, 0]),
        order=3,
    )
    d = _finite_decision(ctrl, 1, [[1.0, 1.0, 0.0], [4.0, 2.0, 0.0]])
    assert d.belief.tolist() == [1.0]
    assert expected_free_energy([1.0], [[0.3], [0.7]]).epistemic == 0.0
    assert variational_free_energy([1.0], [1.0], [0.2]) == pytest.approx(-np.log(0.2))


@pytest.mark.parametrize("sensor", ["range", "bearing"])
def test_one_robot(sensor):
    ctrl = Controller(
        [[3.0, 4.0], [0.0, 0.0]],
        [sensor],
        valid_configurations("allocation", 1, 2),
        order=3,
        horizon=2,
    )
    d = _finite_decision(ctrl, 0, [[3.0, 4.0, 0.0]])
    assert ctrl.configurations[d.focal].tolist() == [0]  # it stands on goal 0


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda c: c.decide(0, [[np.nan, 0.0, 0.0], [1.0, 1.0, 0.0]]), "NaN"),
        (lambda c: c.decide(0, [[0.0, 0.0, 0.0]]), "axis 0 should have length 2"),
        (lambda c: c.decide(2, [[0.0, 0.0], [1.0, 1.0]]), "robot must be"),
        (lambda c: c.decide(0, [[0.0, 0.0], [1.0, 1.0]], prior=[0.5, 0.25]), "sums to"),
        (lambda c: c.decide(0, [[0.0, 0.0], [1.0, 1.0]], prior=[1.0]), "length 2"),
        (lambda c: c.decide(0, [[0.0, 0.0], [1.0, 1.0]], rng=42), "Generator"),
        (lambda c: Controller([[0, 0]], ["range"] * 2, [[0, 1]]), "outside range"),
        (lambda c: Controller([[0, 0]], ["sonar"], [[0]]), "unknown sensor"),
        (lambda c: Controller([[0, 0]], ["range"], [[0]], update="magic"), "unknown update"),
        (lambda c: Controller([[0, 0]], ["range"], [[0, 1]]), "columns"),
        (lambda c: Controller([[0, 0]], ["range"], [[0]], horizon=0), "horizon"),
        (lambda c: Controller([[0, 0]], ["range"], [[0]], horizon=10**6), "at most 64"),
        (lambda c: Controller([[0, 0]], ["range"], [[0]], beam=10**6), "at most 256"),
        (lambda c: Controller([[0, 0]], ["range"], [[0]], progress_weight=np.nan), "NaN"),
        (lambda c: Controller([[0, 0]], ["range"], [[0]], social_weight=-1.0), ">= 0"),
    ],
)
def test_bad_controller_inputs(call, match):
    ctrl = Controller(
        [[5.0, 0.0], [-5.0, 0.0]], ["range", "bearing"], valid_configurations("allocation", 2, 2)
    )
    with pytest.raises(InvalidArgumentError, match=match) as err:
        call(ctrl)
    assert err.value.hint and isinstance(err.value, EpistemicaError)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: bayes_update([0.5, 0.5], [1.0, 1.0, 1.0]), "length 2"),
        (lambda: bayes_update([0.5, 0.5], [np.nan, 1.0]), "NaN"),
        (lambda: bayes_update([1.5, -0.5], [1.0, 1.0]), "negative"),
        (lambda: bayes_update([1.0, 0.0], [0.0, 1.0]), "disjoint"),
        (lambda: bayes_update([0.5, 0.5], [0.0, 0.0]), "zero everywhere"),
        (lambda: expected_free_energy([0.5, 0.5], [[0.5, 0.5], [0.6, 0.5]]), "columns"),
        (lambda: policy_posterior([np.inf, 0.0]), "NaN or infinite"),
        (lambda: select_policy([0.5, 0.6]), "sums to"),
        (lambda: log_likelihood([[0.0, 0.0]], [[0, 1]]), "columns"),
    ],
)
def test_bad_function_inputs(call, match):
    with pytest.raises(InvalidArgumentError, match=match) as err:
        call()
    assert err.value.hint


@settings(max_examples=40, deadline=None)
@given(
    order=st.integers(0, 3),
    update=st.sampled_from(["bayes", "published"]),
    zeros=st.lists(st.booleans(), min_size=6, max_size=6).filter(lambda z: not all(z)),
    gamma=st.sampled_from([0.0, 1.0, 1e12, 1e300]),
    robot=st.integers(0, 1),
)
def test_zero_prior_mass_and_huge_precision_stay_finite(order, update, zeros, gamma, robot):
    """A posterior fed back as a prior has exact zeros: no NaN, no warning, no raw error."""
    ctrl = Controller(
        [[10, 0], [-10, 0], [0, 10]],
        ["range", "bearing"],
        valid_configurations("allocation", 2, 3),
        order=order,
        update=update,
        gamma=gamma,
    )
    prior = np.where(zeros, 0.0, 1.0)
    prior /= prior.sum()
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        d = ctrl.decide(robot, [[1.0, 0.0, 0.0], [-2.0, 1.0, 0.0]], prior=prior)
    assert np.all(np.isfinite(d.G)) and np.isclose(d.q_pi.sum(), 1.0)
    if update == "bayes":  # the published softmax rule is not Bayesian: zeros revive
        assert np.all(d.belief[np.asarray(zeros)] == 0.0)
    assert np.isclose(d.belief.sum(), 1.0)


@pytest.mark.filterwarnings("error")
@settings(max_examples=300, deadline=None)
@given(
    p=arrays(
        np.float64,
        st.integers(1, 6),
        elements=st.one_of(
            st.floats(-1.0, 2.0),
            st.sampled_from([0.0, 0.25, 0.5, 1.0, np.nan, np.inf, -np.inf, 1e-7, -1e-300]),
        ),
    ),
    normalise=st.booleans(),
)
def test_a_distribution_passed_as_an_array_is_checked_like_any_other(p, normalise):
    """A float array takes the short path of ``as_distribution``: it must accept and reject
    exactly what the same values given as a list do."""
    from epistemica.aif._validate import as_distribution

    if normalise and np.isfinite(p).all() and p.sum() > 0:
        p = p / p.sum()

    def outcome(value):
        try:
            return as_distribution(value, "p").tolist()
        except InvalidArgumentError as err:
            return str(err)

    assert outcome(p) == outcome(p.tolist())
