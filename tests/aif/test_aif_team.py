"""The team call returns exactly what one ``decide`` call per robot returns."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif import Controller, valid_configurations
from epistemica.aif.prior import team_log_prior
from epistemica.del_.errors import InvalidArgumentError

FAST = settings(max_examples=40, deadline=None)


@st.composite
def team_scenes(draw):
    """A controller, what every robot observes, and one prior per robot (zeros allowed)."""
    n = draw(st.integers(1, 4))
    mission = draw(st.sampled_from(["rendezvous", "allocation"]))
    m = draw(st.integers(n if mission == "allocation" else 1, 4))
    sensors = draw(st.lists(st.sampled_from(["range", "bearing"]), min_size=n, max_size=n))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    ctrl = Controller(
        rng.uniform(-20, 20, (m, 2)),
        sensors,
        valid_configurations(mission, n, m),
        order=draw(st.integers(1, 3)),
        position_noise=draw(st.sampled_from([0.0, 0.5, 8.0])),
        progress_weight=draw(st.sampled_from([1.0, 30.0])),
        gamma=draw(st.sampled_from([0.5, 5.0])),
    )
    true = np.column_stack([rng.uniform(-20, 20, (n, 2)), rng.uniform(-np.pi, np.pi, n)])
    seen = np.repeat(true[None], n, axis=0)
    seen[..., :2] += rng.normal(0.0, draw(st.sampled_from([0.0, 1.0, 5.0])), (n, n, 2))
    seen[np.arange(n), np.arange(n)] = true  # each robot knows its own pose
    k = ctrl.configurations.shape[0]
    priors = []
    for _ in range(n):
        kind = draw(st.sampled_from(["none", "random", "zeros"]))
        prior = None if kind == "none" else rng.dirichlet(np.ones(k))
        if kind == "zeros" and k > 1:  # what feeding posteriors back produces
            prior[rng.permutation(k)[: k // 2]] = 0.0
            prior /= prior.sum()
        priors.append(prior)
    return ctrl, seen, priors


def assert_same(team, separate):
    """Same decisions and, bit for bit, the same arrays (what the simulator relies on)."""
    assert len(team) == len(separate)
    for t, s in zip(team, separate, strict=True):
        assert (t.index, t.control, t.focal) == (s.index, s.control, s.focal)
        for a, b in ((t.belief, s.belief), (t.G, s.G), (t.q_pi, s.q_pi)):
            np.testing.assert_array_equal(a, b)


@FAST
@given(team_scenes())
def test_team_call_equals_one_call_per_robot(scene):
    ctrl, seen, priors = scene
    separate = [ctrl.decide(i, seen[i], prior=priors[i]) for i in range(len(seen))]
    assert_same(ctrl.decide_team(seen, priors=priors), separate)


@FAST
@given(team_scenes(), st.integers(0, 2**32 - 1), st.randoms(use_true_random=False))
def test_subsets_in_any_order_and_sampled_decisions(scene, seed, shuffle):
    ctrl, seen, priors = scene
    robots = list(range(len(seen)))
    shuffle.shuffle(robots)
    robots = robots[: max(1, len(robots) - 1)]
    mine = [priors[i] for i in robots]
    # One generator: drawn once per robot, in the order of ``robots``.
    rng = np.random.default_rng(seed)
    pairs = list(zip(robots, mine, strict=True))
    separate = [ctrl.decide(i, seen[i], prior=p, rng=rng) for i, p in pairs]
    team = ctrl.decide_team(seen, robots, mine, rng=np.random.default_rng(seed))
    assert_same(team, separate)
    # One generator per robot.
    streams = [np.random.default_rng([seed, i]) for i in robots]
    separate = [
        ctrl.decide(i, seen[i], prior=p, rng=np.random.default_rng([seed, i])) for i, p in pairs
    ]
    assert_same(ctrl.decide_team(seen, robots, mine, rng=streams), separate)


def test_sampling_consumes_the_shared_stream_like_the_loop():
    # A flat policy posterior: the decisions are draws, so a wrong stream shows up.
    ctrl = Controller(
        [[10, 0], [-10, 0]], ["range"] * 3, valid_configurations("rendezvous", 3, 2), gamma=0.0
    )
    seen = np.zeros((3, 3, 3))
    seen[:, :, 0] = [4.0, 0.0, -4.0]
    drawn = [d.index for d in ctrl.decide_team(seen, rng=np.random.default_rng(7))]
    rng = np.random.default_rng(7)
    c = ctrl.controls.shape[0]
    expected = [int(rng.choice(c, p=np.full(c, 1.0 / c))) for _ in range(3)]
    assert drawn == expected and len(set(drawn)) > 1


def test_horizon_and_positions_without_heading():
    rng = np.random.default_rng(4)
    sensors = ["bearing", "range", "range"]
    ctrl = Controller(
        rng.uniform(0, 30, (3, 2)),
        sensors,
        valid_configurations("allocation", 3, 3),
        order=3,
        horizon=2,
    )
    seen = rng.uniform(0, 30, (3, 3, 2))
    separate = [ctrl.decide(i, seen[i]) for i in range(3)]
    assert_same(ctrl.decide_team(seen), separate)


def test_robots_with_different_numbers_of_distinct_moves():
    # At 1e17 m a one-metre move is lost to rounding: robot 1's moves all "stay", so its
    # pass has one column while robot 0's has one per moving control.
    ctrl = Controller([[0, 0], [5, 5]], ["range", "bearing"], [[0, 0], [1, 1]], order=2)
    seen = np.array([[[1.0, 2.0, 0.0], [1e17, 0.0, 0.0]]] * 2)
    team = ctrl.decide_team(seen)
    assert_same(team, [ctrl.decide(i, seen[i]) for i in range(2)])
    assert np.all(team[1].G == team[1].G[0])


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda c, s: c.decide_team(s[:1]), "observations"),
        (lambda c, s: c.decide_team(s[..., :1]), "observations"),
        (lambda c, s: c.decide_team(s, [0, 0]), "distinct"),
        (lambda c, s: c.decide_team(s, [0, 2]), "robot"),
        (lambda c, s: c.decide_team(s, priors=[None]), "priors"),
        (lambda c, s: c.decide_team(s, rng=[np.random.default_rng(0)]), "rng"),
    ],
)
def test_bad_arguments_are_refused(call, match):
    ctrl = Controller([[0, 0], [5, 5]], ["range", "range"], [[0, 0], [1, 1]])
    seen = np.zeros((2, 2, 3))
    with pytest.raises(InvalidArgumentError, match=match):
        call(ctrl, seen)
    assert ctrl.decide_team(seen, []) == []


@FAST
@given(st.integers(1, 5), st.integers(0, 2**32 - 1), st.sampled_from(["rendezvous", "allocation"]))
def test_team_prior_of_several_views_is_each_views_prior(n, seed, mission):
    rng = np.random.default_rng(seed)
    m = n + int(rng.integers(0, 3))
    goals = rng.uniform(0, 30, (m, 2))
    rows = valid_configurations(mission, n, m)
    views = rng.uniform(0, 30, (n, n, 2))
    together = team_log_prior(views, goals, rows, scale=2.0)
    alone = np.stack([team_log_prior(v, goals, rows, scale=2.0) for v in views])
    assert np.array_equal(together, alone)  # bit for bit: the simulator relies on it
    np.testing.assert_allclose(np.exp(together).sum(axis=1), 1.0, atol=1e-12)


# -- nested configuration sets: one prior per modelled perspective ----------------------


def _two_goal_controller(order=2):
    from epistemica.aif.configurations import valid_configurations

    return Controller(
        [[10.0, 0.0], [-10.0, 0.0], [0.0, 10.0]],
        ["range", "bearing", "range"],
        valid_configurations("allocation", 3, 3),
        order=order,
    )


def test_modelled_priors_equal_to_the_prior_change_nothing():
    ctrl = _two_goal_controller()
    poses = [[6.0, 1.0, 0.0], [-5.0, 2.0, 1.0], [1.0, 6.0, 0.0]]
    prior = np.linspace(1.0, 2.0, 6)
    prior /= prior.sum()
    plain = ctrl.decide(0, poses, prior=prior)
    same = ctrl.decide(0, poses, prior=prior, modelled_priors=[prior] * 2)
    assert np.array_equal(plain.G, same.G) and plain.control == same.control


def test_a_modelled_belief_certain_of_the_focal_configuration_adds_a_constant_risk():
    # With a one-hot prior on the focal row, a modelled posterior is that row whatever the
    # move, so its KL to the preference is the same for every candidate; with the plain
    # prior it is not.
    ctrl = _two_goal_controller()
    poses = np.array([[6.0, 1.0, 0.0], [-5.0, 2.0, 1.0], [1.0, 6.0, 0.0]])
    k = ctrl.configurations.shape[0]
    prior = np.full(k, 1.0 / k)
    _, focal = ctrl.beliefs(0, poses)
    onehot = np.zeros(k)
    onehot[focal] = 1.0
    xs = poses[0, :2] + np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.5, 0.5]])
    total = sum(v.weight for v in ctrl.perspectives(0))
    root = _root_risk(ctrl, poses, xs, prior)
    certain = ctrl.evaluate_batch(0, poses[:, :2], xs, prior, np.stack([onehot, onehot], axis=1))
    plain = ctrl.evaluate_batch(0, poses[:, :2], xs, prior)
    assert np.ptp(certain[0].belief_risk * total - root) < 1e-9
    assert np.ptp(plain[0].belief_risk * total - root) > 1e-6


def _root_risk(ctrl, poses, xs, prior):
    """w0 · risk of the root perspective alone, per candidate."""
    from epistemica.aif._logspace import log_softmax

    views = ctrl.perspectives(0)
    pos = poses[:, :2]
    batch = np.concatenate([pos[0][None], xs])
    log_p = log_softmax(ctrl._evidence(views[:1], 0, pos, batch), -1)
    terms = ctrl.model.batch_terms(log_p, np.array([views[0].weight]), 0, batch, prior)[0]
    return terms.belief_risk[1:] * views[0].weight


def test_a_robot_that_models_nobody_takes_an_empty_list_of_modelled_priors():
    # At order 2 a bearing robot among range robots models no teammate's belief.
    ctrl = Controller(
        [[10, 0], [-10, 0], [0, 10]],
        ["bearing", "range", "range"],
        valid_configurations("allocation", 3, 3),
        order=2,
    )
    poses = [[6.0, 1.0, 0.0], [-5.0, 2.0, 1.0], [1.0, 6.0, 0.0]]
    assert len(ctrl.perspectives(0)) == 1
    plain = ctrl.decide(0, poses)
    empty = ctrl.decide(0, poses, modelled_priors=[])
    assert np.array_equal(plain.G, empty.G) and plain.control == empty.control


def test_modelled_priors_are_validated():
    ctrl = _two_goal_controller()
    with pytest.raises(InvalidArgumentError, match="modelled perspectives"):
        ctrl.decide(0, [[6.0, 1.0], [-5.0, 2.0], [1.0, 6.0]], modelled_priors=[None])
