"""Valid configuration sets against brute force and counting formulas."""

from __future__ import annotations

import itertools
from math import comb, factorial, perm

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif import count_configurations, filter_configurations, valid_configurations
from epistemica.del_.errors import InvalidArgumentError


def brute(n, m, keep):
    rows = [c for c in itertools.product(range(m), repeat=n) if keep(c)]
    return np.array(rows, dtype=int).reshape(-1, n)


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 4), st.integers(1, 5))
def test_allocation_equals_distinct_filter_of_all(n, m):
    if n > m:
        with pytest.raises(InvalidArgumentError):
            valid_configurations("allocation", n, m)
        return
    rows = valid_configurations("allocation", n, m)
    expected = brute(n, m, lambda c: len(set(c)) == len(c))
    assert rows.tolist() == expected.tolist()  # same rows, lexicographic order
    assert rows.shape[0] == perm(m, n) == count_configurations("allocation", n, m)


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 3).flatmap(lambda m: st.lists(st.integers(0, 3), min_size=m, max_size=m)))
def test_capacity_equals_count_filter_of_all(caps):
    n, m = sum(caps), len(caps)
    if n == 0:
        return
    rows = valid_configurations("capacity", n, m, capacities=caps)
    expected = brute(n, m, lambda c: all(c.count(g) == caps[g] for g in range(m)))
    assert rows.tolist() == expected.tolist()
    assert rows.shape[0] == count_configurations("capacity", n, m, capacities=caps)


def test_paper_two_goal_example():
    rows = valid_configurations("capacity", 3, 2, capacities=[1, 2])
    assert rows.tolist() == [[0, 1, 1], [1, 0, 1], [1, 1, 0]]


def test_rendezvous_and_all():
    assert valid_configurations("rendezvous", 3, 2).tolist() == [[0, 0, 0], [1, 1, 1]]
    assert valid_configurations("all", 2, 2).tolist() == [[0, 0], [0, 1], [1, 0], [1, 1]]


def test_eight_robots_built_directly():
    rows = valid_configurations("allocation", 8, 8)
    assert rows.shape == (factorial(8), 8) == (40320, 8)
    assert np.all(np.sort(rows, axis=1) == np.arange(8))  # every row a permutation
    assert len({r.tobytes() for r in rows}) == 40320
    # Building it never needs the 8**8 table: the small index type says so too.
    assert rows.nbytes <= 40320 * 8


def test_filters():
    rows = valid_configurations("allocation", 3, 4, where=lambda c: c[:, 0] == 3)
    assert rows.shape[0] == comb(3, 2) * 2 and np.all(rows[:, 0] == 3)
    with pytest.raises(InvalidArgumentError, match="no configuration"):
        filter_configurations(rows, lambda c: c[:, 0] == 0)
    with pytest.raises(InvalidArgumentError, match="filter returned"):
        filter_configurations(rows, lambda c: c[:, 0])


@pytest.mark.parametrize(
    "args, kwargs, match",
    [
        (("teleport", 2, 2), {}, "unknown mission"),
        (("capacity", 3, 2), {}, "needs capacities"),
        (("capacity", 3, 2), {"capacities": [1, 1]}, "sum to 2"),
        (("capacity", 3, 2), {"capacities": [1, 1, 1]}, "capacities must be"),
        (("allocation", 0, 2), {}, "positive integer"),
        (("all", 12, 12), {}, "materialise"),
    ],
)
def test_bad_arguments_raise_with_hint(args, kwargs, match):
    with pytest.raises(InvalidArgumentError, match=match) as err:
        valid_configurations(*args, **kwargs)
    assert err.value.hint
