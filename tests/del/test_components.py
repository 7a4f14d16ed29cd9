"""Common knowledge's components on small models are found without scipy (start-up, issue
38 item 11): the same partition as scipy's graph search, on random partitions."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import connected_components

from epistemica.del_.explicit._sets import _small_components
from epistemica.del_.explicit.relations import Partition


@st.composite
def partitions(draw):
    n = draw(st.integers(1, 40))
    count = draw(st.integers(1, 4))
    return n, [
        Partition(np.array(draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))))
        for _ in range(count)
    ]


@settings(max_examples=200, deadline=None)
@given(partitions())
def test_label_propagation_finds_scipys_components(case):
    n, relations = case
    rows = [np.arange(n) for _ in relations]
    offsets = np.cumsum([n] + [r.n_labels for r in relations])[:-1]
    cols = [offset + r.labels for offset, r in zip(offsets, relations, strict=True)]
    size = int(offsets[-1] + relations[-1].n_labels)
    graph = sp.csr_matrix(
        (np.ones(n * len(relations), dtype=bool), (np.concatenate(rows), np.concatenate(cols))),
        shape=(size, size),
    )
    expected = connected_components(graph, directed=False)[1][:n]
    got = _small_components(relations, n)
    # the same blocks, numbered in the same order (by their first world)
    assert np.array_equal(np.unique(expected, return_inverse=True)[1], got)
