"""Teammate type posteriors (issue 19 §2): Bayes by hand, by law, and on straight motion."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif import valid_configurations
from epistemica.aif.teammates import (
    GOAL_FLOOR,
    TYPE_PRIOR,
    TYPES,
    goal_marginals,
    least_cost_rows,
    mix_configurations,
    motion_log_likelihood,
    type_goal_probabilities,
    update_types,
)

FAST = settings(max_examples=60, deadline=None)
GREEDY, TEAM, STATIONARY = TYPES.index("greedy"), TYPES.index("team"), TYPES.index("stationary")


def _gauss(x, mean, sigma):
    """The isotropic 2-D normal density, written out."""
    d2 = (x[0] - mean[0]) ** 2 + (x[1] - mean[1]) ** 2
    return np.exp(-d2 / (2 * sigma**2)) / (2 * np.pi * sigma**2)


@FAST
@given(
    seed=st.integers(0, 2**32 - 1),
    m=st.integers(1, 5),
    sigma=st.floats(0.2, 3.0),
    reach=st.floats(0.1, 2.0),
)
def test_the_step_likelihood_is_the_goal_mixture_of_normals(seed, m, sigma, reach):
    rng = np.random.default_rng(seed)
    goals = rng.uniform(0, 30, (m, 2))
    previous, current = rng.uniform(0, 30, (1, 2)), rng.uniform(0, 30, (1, 2))
    probs = rng.dirichlet(np.ones(m), size=(1, len(TYPES)))
    got = np.exp(motion_log_likelihood(previous, current, probs, goals, np.array([reach]), sigma))
    for t in range(len(TYPES)):
        if t == STATIONARY:
            expected = _gauss(current[0], previous[0], sigma)
        else:
            expected = 0.0
            for g in range(m):
                delta = goals[g] - previous[0]
                length = np.hypot(*delta)
                step = previous[0] + (min(reach, length) / length if length else 0) * delta
                expected += probs[0, t, g] * _gauss(current[0], step, sigma)
        assert np.isclose(got[0, t], expected, rtol=1e-9, atol=1e-300)


@FAST
@given(
    seed=st.integers(0, 2**32 - 1),
    leak=st.sampled_from([0.0, 0.1]),
)
def test_the_type_update_is_bayes_then_a_leak_to_the_prior(seed, leak):
    rng = np.random.default_rng(seed)
    prior = rng.dirichlet(np.ones(len(TYPES)), size=3)
    ll = rng.normal(0, 5, (3, len(TYPES)))
    got = np.exp(update_types(np.log(prior), ll, leak))
    bayes = prior * np.exp(ll)
    bayes /= bayes.sum(axis=1, keepdims=True)
    assert np.allclose(got, (1 - leak) * bayes + leak * TYPE_PRIOR)
    assert np.allclose(got.sum(axis=1), 1.0)


def test_driving_straight_to_the_nearest_goal_raises_greedy_every_step():
    # Goal 0 is nearest; the team prior expects goal 1: each step straight at goal 0 makes
    # the greedy type more probable.
    goals = np.array([[12.0, 0.0], [0.0, -20.0], [-15.0, 5.0]])
    marginal = np.array([[0.05, 0.9, 0.05]])
    log_types, position, greedy = np.log(TYPE_PRIOR)[None], np.zeros((1, 2)), []
    for _ in range(8):
        probs = type_goal_probabilities(marginal, position, goals, np.array([1]))
        step = position + np.array([[1.0, 0.0]])
        ll = motion_log_likelihood(position, step, probs, goals, np.ones(1), 1.0)
        log_types = update_types(log_types, ll, leak=0.0)
        greedy.append(np.exp(log_types[0, GREEDY]))
        position = step
    assert all(b > a for a, b in itertools.pairwise(greedy))
    assert greedy[-1] > 0.95


def test_a_robot_that_does_not_move_is_read_as_stationary_and_pins_its_goal():
    goals = np.array([[5.0, 5.0], [25.0, 25.0]])
    marginal = np.array([[0.5, 0.5], [0.01, 0.99]])
    positions = np.array([[20.0, 20.0], [5.0, 5.0]])  # robot 1 stands on goal 0
    log_types = np.tile(np.log(TYPE_PRIOR), (2, 1))
    for _ in range(6):
        probs = type_goal_probabilities(marginal, positions, goals, np.array([1, 1]))
        ll = motion_log_likelihood(positions, positions, probs, goals, np.ones(2), 0.5)
        log_types = update_types(log_types, ll, leak=0.0)
    assert TYPES[int(np.argmax(log_types[1]))] == "stationary"
    # The prior had robot 1 leave for goal 1; read as stationary it stays on goal 0, and a
    # rendezvous goes there.
    rows = valid_configurations("rendezvous", 2, 2)
    mask = np.array([[False, True]])
    q = mix_configurations(np.array([[0.01, 0.99]]), log_types[None], probs[None], rows, mask)
    assert rows[np.argmax(q[0])].tolist() == [0, 0]


@FAST
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 4), m=st.integers(2, 4))
def test_the_mixture_for_one_teammate_is_the_type_weighted_conditional(seed, n, m):
    # Independently: sum over types of P(t) · Σ_g P_t(g) · prior(c | c_j = g).
    rng = np.random.default_rng(seed)
    rows = valid_configurations("allocation", n, m) if m >= n else np.array([[0] * n])
    prior = rng.dirichlet(np.ones(rows.shape[0]))
    j = int(rng.integers(n))
    types = rng.dirichlet(np.ones(len(TYPES)))
    probs = rng.dirichlet(np.ones(m), size=(n, len(TYPES)))
    log_types = np.tile(np.log(types), (n, 1))
    mask = np.arange(n) == j
    got = mix_configurations(prior[None], log_types[None], probs[None], rows, mask[None])[0]
    expected = np.zeros(rows.shape[0])
    for t in range(len(TYPES)):
        flat = t == TEAM or np.allclose(probs[j, t], 1 / m)
        for c in range(rows.shape[0]):
            if flat:
                expected[c] += types[t] * prior[c]
                continue
            g = rows[c, j]
            marginal = prior[rows[:, j] == g].sum()
            expected[c] += types[t] * probs[j, t, g] * prior[c] / marginal
    assert np.allclose(got, expected / expected.sum())


def test_a_team_teammate_leaves_the_prior_unchanged():
    rows = valid_configurations("allocation", 3, 3)
    prior = np.random.default_rng(1).dirichlet(np.ones(rows.shape[0]))
    probs = np.random.default_rng(2).dirichlet(np.ones(3), size=(3, len(TYPES)))
    log_types = np.log(np.tile([1.0, 1e-300, 1e-300, 1e-300], (3, 1)))
    mask = np.array([[True, False, True]])
    got = mix_configurations(prior[None], log_types[None], probs[None], rows, mask)
    assert np.allclose(got[0], prior)


def test_type_goal_predictions_by_hand():
    goals = np.array([[0.0, 0.0], [10.0, 0.0]])
    marginal = np.array([[0.3, 0.7], [0.6, 0.4]])
    positions = np.array([[8.0, 0.0], [0.2, 0.1]])  # robot 1 stands on goal 0
    probs = type_goal_probabilities(marginal, positions, goals, np.array([0, 0]))
    hot = [GOAL_FLOOR, 1 - GOAL_FLOOR]
    assert np.allclose(probs[0, TEAM], [0.3, 0.7])
    assert np.allclose(probs[0, GREEDY], hot)  # goal 1 is 2 m away, goal 0 8 m
    assert np.allclose(probs[0, TYPES.index("convention")], hot[::-1])
    assert np.allclose(probs[0, STATIONARY], [0.5, 0.5])  # on no goal: flat
    assert np.allclose(probs[1, STATIONARY], hot[::-1])


def test_least_cost_rows_against_brute_force():
    rng = np.random.default_rng(5)
    views, goals = rng.uniform(0, 30, (3, 4, 2)), rng.uniform(0, 30, (5, 2))
    rows = valid_configurations("allocation", 4, 5)
    got = least_cost_rows(views, goals, rows)
    for view, row in zip(views, got, strict=True):
        cost = [sum(np.hypot(*(view[r] - goals[c[r]])) for r in range(4)) for c in rows]
        assert row.tolist() == rows[int(np.argmin(cost))].tolist()


@FAST
@given(seed=st.integers(0, 2**32 - 1), observers=st.integers(1, 3))
def test_goal_marginals_sum_the_prior_by_goal(seed, observers):
    rng = np.random.default_rng(seed)
    rows = valid_configurations("allocation", 3, 4)
    prior = rng.dirichlet(np.ones(rows.shape[0]), size=observers)
    got = goal_marginals(prior, rows, 4)
    for r, j, g in itertools.product(range(observers), range(3), range(4)):
        assert np.isclose(got[r, j, g], prior[r, rows[:, j] == g].sum())


@FAST
@given(seed=st.integers(0, 2**32 - 1))
def test_the_batched_mixture_is_the_mixture_of_each_observer(seed):
    rng = np.random.default_rng(seed)
    rows = valid_configurations("rendezvous", 4, 3)
    prior = rng.dirichlet(np.ones(rows.shape[0]), size=3)
    log_types = np.log(rng.dirichlet(np.ones(len(TYPES)), size=(3, 4)))
    probs = rng.dirichlet(np.ones(3), size=(3, 4, len(TYPES)))
    mask = rng.random((3, 4)) < 0.6
    together = mix_configurations(prior, log_types, probs, rows, mask)
    for r in range(3):
        alone = mix_configurations(prior[r : r + 1], log_types[r : r + 1], probs[r : r + 1],
                                   rows, mask[r : r + 1])  # fmt: skip
        assert np.allclose(together[r], alone[0])


def test_two_teammates_holding_clashing_goals_do_not_outvote_a_certain_one():
    # Rendezvous of 4 at goals 0/1: robot 1 is certainly greedy for goal 1; robots 2 and 3,
    # waiting at goal 0, are 60 % team and 40 % committed there. By the first-order
    # expansion (at most one teammate holds a goal of its own), computed by hand:
    # goal 0: π0 · (u1 u2 u3) + π0 · [a2 u1 u3 + a3 u1 u2] / π0 with u1 ≈ 0,
    # goal 1: π1 · [a1 u2 u3] / π1 = 0.36 -> goal 1 wins although π favours goal 0.
    rows = valid_configurations("rendezvous", 4, 2)
    prior = np.array([[0.99, 0.01]])
    log_types = np.log(np.array([[
        [0.97, 0.01, 0.01, 0.01],
        [1e-12, 1.0, 1e-12, 1e-12],
        [0.6, 0.4, 1e-12, 1e-12],
        [0.6, 0.4, 1e-12, 1e-12],
    ]]))  # fmt: skip
    probs = np.full((1, 4, len(TYPES), 2), 0.5)
    probs[0, 1, GREEDY] = [0.0, 1.0]
    probs[0, 2:, GREEDY] = [1.0, 0.0]
    q = mix_configurations(prior, log_types, probs, rows, np.array([[False, True, True, True]]))
    expected = np.array([0.99 * 1e-12 * 0.36 + 2 * 0.4 * 1e-12 * 0.6, 0.36])
    assert np.allclose(q[0], expected / expected.sum())
