"""Sparse row sums over valid rows, and the one-step terms from their definitions."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from epistemica.aif import bayes_update, mutual_information, valid_configurations
from epistemica.aif.one_step import OneStepEFE
from epistemica.aif.row_index import RowIndex
from epistemica.del_.errors import InvalidArgumentError

FAST = settings(max_examples=30, deadline=None)


@st.composite
def valid_sets_and_tables(draw):
    n, m, b = draw(st.integers(1, 4)), draw(st.integers(1, 4)), draw(st.integers(1, 3))
    every = list(itertools.product(range(m), repeat=n))
    rows = draw(st.lists(st.sampled_from(every), min_size=1, max_size=12, unique=True))
    tables = draw(arrays(float, (b, n, m), elements=st.floats(-5, 5)))
    return np.array(rows), m, tables


@FAST
@given(valid_sets_and_tables())
def test_row_sums_gather_each_robots_goal(case):
    rows, m, tables = case
    got = RowIndex(rows, m).row_sums(tables)
    want = [[sum(t[r, c[r]] for r in range(rows.shape[1])) for t in tables] for c in rows]
    np.testing.assert_allclose(got, want, atol=1e-12)
    got32 = RowIndex(rows, m, dtype=np.float32).row_sums(tables)
    np.testing.assert_allclose(got32, want, atol=1e-4)


@FAST
@given(valid_sets_and_tables(), st.data())
def test_groups_mark_the_goal_of_each_row(case, data):
    rows, m, _ = case
    robot = data.draw(st.integers(0, rows.shape[1] - 1))
    dense = RowIndex(rows, m).groups(robot).toarray()
    assert dense.tolist() == [[float(c[robot] == g) for c in rows] for g in range(m)]


def test_terms_match_definitions_on_a_hand_built_case():
    goals = [[10.0, 0.0], [-10.0, 0.0], [0.0, 10.0]]
    configs = valid_configurations("allocation", 2, 3)  # 6 rows
    eps, eta = 0.05, 20.0
    model = OneStepEFE(goals, configs, preference_floor=eps, eta=eta)
    rng = np.random.default_rng(3)
    log_p = np.log(rng.dirichlet(np.ones(3), size=(1, 3, 2)))  # root only, 3 columns
    positions = np.array([[1.0, 2.0], [3.0, -1.0], [-4.0, 0.5]])
    prior = rng.dirichlet(np.ones(6))
    terms, q_root, focal = model.terms(log_p, [1.0], 0, positions, prior)
    k = configs.shape[0]

    def likelihood(col):
        return np.array([np.exp(log_p[0, col, 0, c[0]] + log_p[0, col, 1, c[1]]) for c in configs])

    q0 = bayes_update(prior, likelihood(0))
    np.testing.assert_allclose(q_root, q0, atol=1e-12)
    assert focal == int(np.argmax(q0))
    pref = np.full(k, eps / k)
    pref[focal] += 1 - eps
    g_star = np.array(goals[configs[focal, 0]])
    for col in range(3):
        L = likelihood(col)
        q = bayes_update(prior, L)
        kl = float(np.sum(q * np.log(q / pref)))
        ell = L / L.max()
        reading = np.log(2) - mutual_information(q0, np.vstack([ell, 1 - ell]))
        assert terms.progress[col] == pytest.approx(np.linalg.norm(positions[col] - g_star) / eta)
        assert terms.belief_risk[col] == pytest.approx(kl, abs=1e-10)
        assert terms.reading[col] == pytest.approx(reading, abs=1e-10)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda m: m.terms(np.zeros((1, 1, 2, 2)), [0.0], 0, [[0.0, 0.0]]), "weights"),
        (lambda m: m.terms(np.zeros((1, 1, 2, 2)), [1.0, 1.0], 0, [[0.0, 0.0]]), "length 1"),
        (lambda m: m.terms(np.zeros((1, 1, 2, 3)), [1.0], 0, [[0.0, 0.0]]), "axis 3"),
        (lambda m: m.terms(np.zeros((1, 2, 2, 2)), [1.0], 0, [[0.0, 0.0]]), "axis 0"),
        (lambda m: m.terms(np.zeros((1, 1, 2, 2)), [1.0], 5, [[0.0, 0.0]]), "robot must be"),
        (lambda m: m.posterior_log(np.full((1, 2, 2), np.nan)), "NaN"),
        (lambda m: OneStepEFE([[0, 0], [1, 0]], [[0, 1]], update="magic"), "unknown update"),
        (lambda m: OneStepEFE([[0, 0], [1, 0]], [[0, 1]], chunk_cells=0), "chunk_cells"),
        (lambda m: RowIndex([[0, 1]], 2, dtype=int), "dtype"),
        (lambda m: RowIndex([[0, 1]], 2).row_sums(np.zeros((1, 2, 3))), "tables"),
        (lambda m: RowIndex([[0, 1]], 2).groups(2), "robot must be"),
    ],
)
def test_bad_one_step_inputs(call, match):
    model = OneStepEFE([[0.0, 0.0], [1.0, 0.0]], [[0, 1], [1, 0]])
    with pytest.raises(InvalidArgumentError, match=match) as err:
        call(model)
    assert err.value.hint
