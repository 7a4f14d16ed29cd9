"""The team prior and the plausible configurations, against brute force and by law."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif import valid_configurations
from epistemica.aif.prior import (
    lexicographic_order,
    plausible_configurations,
    shared_rank,
    team_log_prior,
)

FAST = settings(max_examples=60, deadline=None)


@FAST
@given(
    case=st.sampled_from([("rendezvous", None), ("allocation", None), ("capacity", "caps")]),
    n=st.integers(1, 6),
    extra=st.integers(0, 2),
    within=st.floats(0.0, 40.0),
    seed=st.integers(0, 2**32 - 1),
)
def test_plausible_set_equals_filtering_the_valid_set(case, n, extra, within, seed):
    mission, caps = case
    rng = np.random.default_rng(seed)
    m = n + extra
    if caps:
        caps = rng.multinomial(n, np.ones(m) / m)
    cost = rng.uniform(0, 30, (n, m))
    rows = valid_configurations(mission, n, m, caps)
    total = cost[np.arange(n), rows].sum(axis=1)
    expected = rows[total <= total.min() + within + 1e-9]
    got = plausible_configurations(cost, mission, caps, within=within)
    assert np.array_equal(got, expected)


def test_the_beam_keeps_the_least_cost_configuration():
    rng = np.random.default_rng(3)
    cost = rng.uniform(0, 30, (7, 7))
    rows = valid_configurations("allocation", 7, 7)
    best = rows[np.argmin(cost[np.arange(7), rows].sum(axis=1))]
    beam = plausible_configurations(cost, "allocation", within=1e9, limit=10)
    assert len(beam) <= 10 and any(np.array_equal(best, r) for r in beam)


@FAST
@given(seed=st.integers(0, 2**32 - 1), k=st.integers(1, 30))
def test_shared_rank_is_a_permutation_computed_alike(seed, k):
    rng = np.random.default_rng(seed)
    goals = rng.uniform(0, 30, (4, 2))
    rows = rng.integers(0, 4, (k, 3))
    rows = np.unique(rows, axis=0)
    r1, r2 = shared_rank(goals, rows), shared_rank(goals.copy(), rows.copy())
    assert np.array_equal(r1, r2)
    assert sorted(r1.tolist()) == (np.arange(len(rows)) / max(len(rows) - 1, 1)).tolist()


@FAST
@given(seed=st.integers(0, 2**32 - 1), scale=st.floats(0.1, 10), tie=st.floats(0, 3))
def test_team_prior_is_normalised_and_orders_by_cost(seed, scale, tie):
    rng = np.random.default_rng(seed)
    positions, goals = rng.uniform(0, 30, (3, 2)), rng.uniform(0, 30, (3, 2))
    rows = valid_configurations("allocation", 3, 3)
    lp = team_log_prior(positions, goals, rows, scale=scale, tie_weight=tie)
    assert np.exp(lp).sum() == pytest.approx(1.0)
    cost = np.hypot(*(positions[:, None] - goals[None]).transpose(2, 0, 1))[np.arange(3), rows].sum(
        1
    )
    rank = shared_rank(goals, rows)
    # log odds = -(cost difference)/scale - tie * (rank difference), exactly
    i, j = 0, len(rows) - 1
    assert lp[i] - lp[j] == pytest.approx(-(cost[i] - cost[j]) / scale - tie * (rank[i] - rank[j]))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10**6), st.integers(4, 8), st.sampled_from([1, 3, 10]))
def test_a_narrow_beam_still_keeps_the_least_cost_configuration(seed, n, limit):
    # The beam ranks prefixes by a bound that ignores distinctness; prefixes it prefers
    # can all die later. The least-cost configuration must survive whatever the beam.
    from scipy.optimize import linear_sum_assignment

    cost = np.random.default_rng(seed).uniform(0, 30, size=(n, n))
    rows = plausible_configurations(cost, "allocation", within=5.0, limit=limit)
    r, c = linear_sum_assignment(cost)
    best = np.empty(n, dtype=int)
    best[r] = c
    assert rows.shape[0] >= 1
    assert (rows == best).all(axis=1).any()


@FAST
@given(
    k=st.integers(1, 40),
    n=st.integers(1, 12),
    top=st.sampled_from([1, 2, 5, 40, 2**40]),  # the last overflows the one-number key
    seed=st.integers(0, 2**32 - 1),
)
def test_lexicographic_order_is_lexsorts(k, n, top, seed):
    rows = np.random.default_rng(seed).integers(0, top, (k, n))
    assert lexicographic_order(rows).tolist() == np.lexsort(rows.T[::-1]).tolist()


@FAST
@given(seed=st.integers(0, 2**32 - 1), m=st.integers(1, 6), k=st.integers(1, 30))
def test_shared_rank_orders_by_the_goals_coordinates(seed, m, k):
    # Coordinates on a coarse grid (equal goals, -0.0 beside 0.0): the rank must be the
    # stable lexicographic order of each row's (x, y) of robot 0's goal, robot 1's, ...
    rng = np.random.default_rng(seed)
    goals = rng.integers(-1, 2, (m, 2)).astype(float)
    goals[goals == 0] *= rng.choice([-1.0, 1.0], size=int((goals == 0).sum()))
    rows = rng.integers(0, m, (k, 3))
    keys = goals[rows].reshape(k, -1)
    order = np.lexsort(keys.T[::-1])
    expected = np.empty(k)
    expected[order] = np.arange(k) / max(k - 1, 1)
    assert shared_rank(goals, rows).tolist() == expected.tolist()
