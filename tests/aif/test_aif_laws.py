"""Property-based tests of the laws of beliefs, information and free energy."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from epistemica.aif import (
    bayes_update,
    configuration_likelihood,
    entropy,
    expected_free_energy,
    goal_log_probabilities,
    joint_observation_model,
    kl_divergence,
    log_likelihood,
    mutual_information,
    policy_posterior,
    published_update,
    select_policy,
    total_correlation,
    valid_configurations,
    variational_free_energy,
)

FAST = settings(max_examples=30, deadline=None)


def distributions(size: int | None = None, min_size: int = 1, max_size: int = 8):
    """Probability vectors, exact zeros included (a posterior fed back as a prior has them)."""
    n = st.just(size) if size is not None else st.integers(min_size, max_size)
    weight = st.one_of(st.just(0.0), st.floats(0.01, 1.0))
    return n.flatmap(
        lambda k: (
            arrays(float, k, elements=weight)
            .filter(lambda w: w.sum() > 0)
            .map(lambda w: w / w.sum())
        )
    )


def likelihoods(size: int):
    return arrays(float, size, elements=st.floats(0.001, 1.0))


@st.composite
def prior_and_likelihoods(draw, count: int = 1):
    prior = draw(distributions())
    return (prior, *[draw(likelihoods(prior.size)) for _ in range(count)])


@st.composite
def observation_models(draw, max_states=5, max_outcomes=4):
    """A state distribution and a column-stochastic P(o | s)."""
    n_s = draw(st.integers(1, max_states))
    n_o = draw(st.integers(1, max_outcomes))
    qs = draw(distributions(n_s))
    raw = draw(arrays(float, (n_o, n_s), elements=st.floats(0.0, 1.0)))
    raw[0] += 0.05  # every column has some mass
    return qs, raw / raw.sum(axis=0)


@FAST
@given(prior_and_likelihoods())
def test_posterior_is_a_distribution(args):
    prior, like = args
    for q in (bayes_update(prior, like), published_update(prior, like)):
        assert np.all(q >= 0)
        assert q.sum() == pytest.approx(1.0, abs=1e-12)


@FAST
@given(distributions(), st.floats(0.01, 10.0))
def test_uniform_likelihood_leaves_prior_unchanged(prior, level):
    np.testing.assert_allclose(bayes_update(prior, np.full(prior.size, level)), prior, atol=1e-12)


@FAST
@given(prior_and_likelihoods(count=2))
def test_sequential_updates_commute(args):
    prior, l1, l2 = args
    a = bayes_update(bayes_update(prior, l1), l2)
    b = bayes_update(bayes_update(prior, l2), l1)
    both = bayes_update(prior, l1 * l2)
    np.testing.assert_allclose(a, b, atol=1e-12)
    np.testing.assert_allclose(a, both, atol=1e-12)


def test_bayes_update_hand_worked():
    # q ∝ (.1 * .3, .8 * .7) = (.03, .56) -> (.03 / .59, .56 / .59)
    np.testing.assert_allclose(bayes_update([0.3, 0.7], [0.1, 0.8]), [0.03 / 0.59, 0.56 / 0.59])


def test_published_update_hand_worked():
    # softmax(.2 * (1, 0) + .8 * (.5, .5)) = softmax(.6, .4)
    e = np.exp([0.6, 0.4])
    np.testing.assert_allclose(published_update([0.5, 0.5], [1.0, 0.0]), e / e.sum())


@FAST
@given(st.integers(1, 6).flatmap(lambda k: st.tuples(distributions(k), distributions(k))))
def test_kl_nonnegative_zero_iff_equal(pq):
    p, q = pq
    d = kl_divergence(p, q)
    assert d >= 0
    assert kl_divergence(p, p) == 0.0
    if not np.allclose(p, q, atol=1e-6):
        assert d > 0
    else:
        assert d == pytest.approx(0.0, abs=1e-9)


@st.composite
def beliefs_over_valid_sets(draw):
    n = draw(st.integers(1, 4))
    m = draw(st.integers(n, 5))
    mission = draw(st.sampled_from(["allocation", "rendezvous"]))
    configs = valid_configurations(mission, n, m)
    evidence = draw(arrays(float, (n, m), elements=st.floats(-30.0, 30.0)))
    prior = draw(distributions(configs.shape[0]))
    return configs, evidence, prior


@FAST
@given(beliefs_over_valid_sets())
def test_entropy_between_zero_and_log_of_valid_set(args):
    configs, evidence, prior = args
    L = np.exp(log_likelihood(goal_log_probabilities(evidence), configs))
    q = bayes_update(prior, L)
    h = entropy(q)
    assert -1e-12 <= h <= np.log(configs.shape[0]) + 1e-12


def test_entropy_bounds_attained():
    assert entropy([1.0, 0.0, 0.0]) == 0.0
    assert entropy(np.full(24, 1 / 24)) == pytest.approx(np.log(24))


@FAST
@given(observation_models(), st.integers(1, 4))
def test_uninformative_control_has_zero_epistemic_value(model, n_o):
    qs, _ = model
    column = np.random.default_rng(n_o).dirichlet(np.ones(n_o))
    A = np.repeat(column[:, None], qs.size, axis=1)  # P(o | s) the same for every s
    efe = expected_free_energy(qs, A)
    assert efe.epistemic == pytest.approx(0.0, abs=1e-12)
    assert mutual_information(qs, A) == pytest.approx(0.0, abs=1e-12)


@FAST
@given(observation_models(), st.data())
def test_efe_decompositions_agree(model, data):
    qs, A = model
    c = data.draw(arrays(float, A.shape[0], elements=st.floats(-5.0, 5.0)))
    efe = expected_free_energy(qs, A, c)
    assert efe.G == pytest.approx(efe.risk + efe.ambiguity, abs=1e-9)
    assert efe.G == pytest.approx(-(efe.pragmatic + efe.epistemic), abs=1e-9)
    assert efe.risk >= 0 and efe.ambiguity >= 0
    # Independent check of risk: KL[Q(o) || softmax(c)].
    pref = np.exp(c - c.max())
    pref /= pref.sum()
    qo = A @ qs
    assert efe.risk == pytest.approx(kl_divergence(qo / qo.sum(), pref), abs=1e-9)
    assert 0.0 <= efe.epistemic <= entropy(qs) + 1e-9


@FAST
@given(st.integers(1, 4).flatmap(lambda k: st.tuples(observation_models(), st.just(k))))
def test_joint_information_is_per_modality_sum_minus_total_correlation(args):
    (qs, A1), seed = args
    rng = np.random.default_rng(seed)
    A2 = rng.dirichlet(np.ones(3), size=qs.size).T
    joint = joint_observation_model(A1, A2)
    i_joint = mutual_information(qs, joint)
    i_sum = mutual_information(qs, A1) + mutual_information(qs, A2)
    tc = total_correlation((joint @ qs).reshape(A1.shape[0], 3))
    assert i_sum - i_joint == pytest.approx(tc, abs=1e-9)
    assert i_joint <= i_sum + 1e-12


@FAST
@given(prior_and_likelihoods(), st.data())
def test_vfe_bounds_surprise_with_equality_at_posterior(args, data):
    prior, like = args
    like = like / like.max()
    surprise = -np.log(like @ prior)
    post = bayes_update(prior, like)
    assert variational_free_energy(post, prior, like) == pytest.approx(surprise, abs=1e-9)
    q = data.draw(distributions(prior.size))
    gap = variational_free_energy(q, prior, like) - surprise
    assert gap == pytest.approx(kl_divergence(q, post), abs=1e-9)


@st.composite
def products_with_invalid_mass(draw):
    n = draw(st.integers(1, 3))
    m = draw(st.integers(n, 4))
    mission = draw(st.sampled_from(["allocation", "rendezvous"]))
    p = draw(arrays(float, (n, m), elements=st.floats(0.01, 1.0)))
    p = p / p.sum(axis=1, keepdims=True)
    extra = draw(arrays(float, (m,) * n, elements=st.floats(0.0, 50.0)))
    return mission, n, m, p, extra


@FAST
@given(products_with_invalid_mass())
def test_invalid_mass_never_changes_likelihood(args):
    mission, n, m, p, extra = args
    valid = valid_configurations(mission, n, m)
    # The paper's route: the full m**n product table, restricted and renormalised...
    table = np.ones((m,) * n)
    for r in range(n):
        shape = [1] * n
        shape[r] = m
        table = table * p[r].reshape(shape)
    is_valid = np.zeros((m,) * n, dtype=bool)
    is_valid[tuple(valid.T)] = True
    # ...after piling arbitrary extra mass on every invalid configuration.
    table = table + np.where(is_valid, 0.0, extra)
    restricted = table[tuple(valid.T)]
    np.testing.assert_allclose(
        configuration_likelihood(p, valid), restricted / restricted.sum(), atol=1e-12
    )


def test_likelihood_against_brute_force_product():
    p = np.array([[0.2, 0.5, 0.3], [0.6, 0.1, 0.3]])
    valid = valid_configurations("allocation", 2, 3)
    brute = np.array([p[0, a] * p[1, b] for a, b in itertools.permutations(range(3), 2)])
    np.testing.assert_allclose(configuration_likelihood(p, valid), brute / brute.sum())


@FAST
@given(arrays(float, st.integers(1, 10), elements=st.floats(-20, 20)), st.floats(0.0, 20.0))
def test_policy_posterior_is_a_distribution(G, gamma):
    q = policy_posterior(G, gamma)
    assert q.sum() == pytest.approx(1.0, abs=1e-12)
    assert np.all(q >= 0)
    assert select_policy(q) == int(np.argmax(q))


def test_policy_posterior_gamma_zero_is_prior():
    np.testing.assert_allclose(policy_posterior([3.0, 1.0, 2.0], 0.0), [1 / 3] * 3)
    np.testing.assert_allclose(
        policy_posterior([3.0, 1.0], 0.0, log_prior=np.log([0.25, 0.75])), [0.25, 0.75]
    )


def test_sampled_selection_is_reproducible_and_follows_q():
    q = np.array([0.1, 0.6, 0.3])
    a = [select_policy(q, np.random.default_rng(7)) for _ in range(5)]
    assert len(set(a)) == 1
    rng = np.random.default_rng(1)
    counts = np.bincount([select_policy(q, rng) for _ in range(3000)], minlength=3) / 3000
    np.testing.assert_allclose(counts, q, atol=0.04)


def test_information_hand_worked():
    assert kl_divergence([0.8, 0.2], [0.5, 0.5]) == pytest.approx(
        0.8 * np.log(1.6) + 0.2 * np.log(0.4)
    )
    # A binary symmetric channel with error .1 on a fair bit: ln 2 - h(.1).
    h = -(0.1 * np.log(0.1) + 0.9 * np.log(0.9))
    assert mutual_information([0.5, 0.5], [[0.9, 0.1], [0.1, 0.9]]) == pytest.approx(np.log(2) - h)
