"""The shared checks of log-probability arguments, through every public function using them."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.aif import (
    bayes_update_log,
    count_configurations,
    log_likelihood,
    policy_posterior,
    uniform_belief,
)
from epistemica.del_.errors import InvalidArgumentError


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: bayes_update_log([0.0, np.nan], [0.0, 0.0]), "log_prior must not contain NaN"),
        (lambda: bayes_update_log([0.0, 0.0], [np.inf, 0.0]), "log_likelihood must not"),
        (lambda: bayes_update_log([0.0, 0.0], [0.0, 0.0, 0.0]), "axis 0 should have length 2"),
        (lambda: bayes_update_log([[0.0]], [[0.0]]), "1 dimension"),
        (lambda: bayes_update_log([0.0, -np.inf], [-np.inf, 0.0]), "disjoint"),
        (lambda: bayes_update_log(["a", "b"], [0.0, 0.0]), "numeric"),
        (lambda: log_likelihood([[0.0, np.inf]], [[0]]), "log_p must not contain"),
        (lambda: log_likelihood([0.0, 0.0], [[0]]), "2 dimension"),
        (lambda: log_likelihood([[-np.inf, 0.0]], [[0]]), "probability zero"),
        (lambda: policy_posterior([1.0, 2.0], log_prior=[0.0]), "length 2"),
        (lambda: policy_posterior([1.0, 2.0], log_prior=[np.nan, 0.0]), "NaN"),
        (lambda: policy_posterior([1.0, 2.0], log_prior=[-np.inf, -np.inf]), "zero prior"),
        (lambda: uniform_belief(0), "positive integer"),
        (lambda: uniform_belief(True), "positive integer"),
        (lambda: count_configurations("all", 2, 0), "n_goals must be a positive integer"),
    ],
)
def test_bad_log_arguments_raise_with_hint(call, match):
    with pytest.raises(InvalidArgumentError, match=match) as err:
        call()
    assert err.value.hint


def test_impossible_states_stay_impossible():
    # -inf is a legal log probability: such states get exactly zero mass.
    q = np.exp(bayes_update_log(np.log([0.5, 0.25, 0.25]), [0.0, -np.inf, np.log(3.0)]))
    np.testing.assert_allclose(q, [0.4, 0.0, 0.6])
    np.testing.assert_allclose(policy_posterior([0.0, 0.0], log_prior=[0.0, -np.inf]), [1, 0])
