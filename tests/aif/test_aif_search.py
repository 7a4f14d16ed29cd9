"""Receding-horizon search and pruning against exhaustive enumeration."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif.search import prune_dominated, receding_horizon
from epistemica.del_.errors import InvalidArgumentError

FAST = settings(max_examples=40, deadline=None)


def step_by_hand(pose, control, dt):
    """Turn first, then move speed * dt along the new heading (the documented dynamics)."""
    x, y, h = pose
    v, dh = control
    h = h + dh
    return (x + v * dt * math.cos(h), y + v * dt * math.sin(h), h)


@st.composite
def problems(draw):
    c = draw(st.integers(1, 4))
    speeds = draw(st.lists(st.sampled_from([0.0, 0.5, 1.0]), min_size=c, max_size=c))
    turns = draw(
        st.lists(st.sampled_from([0.0, math.pi / 2, -math.pi / 2, math.pi]), min_size=c, max_size=c)
    )
    target = draw(st.tuples(st.floats(-3, 3), st.floats(-3, 3)))
    horizon = draw(st.integers(1, 3))
    dt = draw(st.sampled_from([0.5, 1.0]))
    return np.column_stack([speeds, turns]), target, horizon, dt


@FAST
@given(problems())
def test_receding_horizon_equals_exhaustive_search(problem):
    controls, (tx, ty), horizon, dt = problem
    c = controls.shape[0]

    def cost_at(x, y):
        return math.hypot(x - tx, y - ty)

    start = (0.0, 0.0, 0.3)
    first = np.array([step_by_hand(start, u, dt) for u in controls])
    first_cost = np.array([cost_at(p[0], p[1]) for p in first])
    got = receding_horizon(
        lambda xy: np.hypot(xy[:, 0] - tx, xy[:, 1] - ty),
        first,
        first_cost,
        controls,
        dt,
        horizon,
        beam=c ** max(horizon - 1, 1),  # wide enough that only dominated branches go
    )
    want = []
    for a in range(c):
        best = math.inf
        for rest in itertools.product(range(c), repeat=horizon - 1):
            pose, total = tuple(first[a]), first_cost[a]
            for u in rest:
                pose = step_by_hand(pose, controls[u], dt)
                total += cost_at(pose[0], pose[1])
            best = min(best, total)
        want.append(best)
    np.testing.assert_allclose(got, want, atol=1e-7)


@FAST
@given(
    st.lists(
        st.tuples(st.integers(0, 3), st.integers(0, 2), st.floats(0, 10), st.booleans()),
        min_size=1,
        max_size=25,
    ),
    st.integers(1, 4),
)
def test_pruning_keeps_the_cheapest_distinct_poses(rows, beam):
    pool = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 0.0, math.pi / 2), (0.0, 2.0, -1.0)]
    # A heading shifted by a full turn is the same pose.
    nodes = [
        (*pool[p][:2], pool[p][2] + (2 * math.pi if turned else 0.0)) for p, _, _, turned in rows
    ]
    origin = np.array([o for _, o, _, _ in rows])
    cost = np.array([w for _, _, w, _ in rows])
    kept_nodes, kept_cost, kept_origin = prune_dominated(nodes, cost, origin, beam)
    for o in set(origin.tolist()):
        # Independent: the cheapest branch per distinct pose, then the `beam` cheapest.
        per_pose: dict[int, float] = {}
        for p, oo, w, _ in rows:
            if oo == o:
                per_pose[p] = min(per_pose.get(p, math.inf), w)
        want = sorted(per_pose.values())[:beam]
        mine = kept_origin == o
        assert sorted(kept_cost[mine].tolist()) == want
        poses = {
            tuple(np.round([x, y, math.remainder(h, 2 * math.pi)], 6))
            for x, y, h in kept_nodes[mine]
        }
        assert len(poses) == np.count_nonzero(mine)  # no two kept branches share a pose
    assert np.all(np.diff(kept_origin) >= 0)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: prune_dominated([[0.0, 0.0, 0.0]], [1.0], [0], beam=0), "beam"),
        (lambda: prune_dominated([[0.0, 0.0, 0.0]], [1.0, 2.0], [0], beam=1), "cost and origin"),
        (lambda: prune_dominated([[0.0, 0.0]], [1.0], [0], beam=1), "axis 1"),
        (
            lambda: receding_horizon(np.sum, [[0.0, 0.0, 0.0]], [1.0], [[1.0, 0.0]], horizon=0),
            "horizon",
        ),
        (
            lambda: receding_horizon(np.sum, [[0.0, 0.0, 0.0]], [1.0, 2.0], [[1.0, 0.0]]),
            "first_cost",
        ),
    ],
)
def test_bad_search_inputs(call, match):
    with pytest.raises(InvalidArgumentError, match=match) as err:
        call()
    assert err.value.hint
