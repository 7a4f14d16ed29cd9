"""The planning controller (epistemica.aif.planning): hand-worked plans and laws."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica import InvalidArgumentError
from epistemica.aif.configurations import valid_configurations
from epistemica.aif.planning import WAIT, Planner, motion_evidence

GOALS = [[0.0, 0.0], [10.0, 0.0]]
MEET = [[0, 0], [1, 1]]  # two robots, rendezvous at goal 0 or goal 1


def test_expected_completion_time_by_hand():
    # Order 1, no sets: robot 1 is predicted at order 0 from the prior (uniform over the
    # two meetings) times its position's evidence exp(-d / eta). eta = 5 x 10 m.
    planner = Planner(GOALS, MEET, [1.0, 1.0], order=1, temperature=1.0, repair=1.0,
                      success_weight=0.0)  # fmt: skip
    positions = np.array([[4.0, 0.0], [10.0, 0.0]])
    result = planner.plan(0, positions)
    eta, repair, tau = 50.0, 10.0, 10.0  # diameter 10 m at speed 1; D / v = 10 s
    pi1 = np.exp(-np.array([10.0, 0.0]) / eta)
    pi1 /= pi1.sum()
    # Meeting at goal g ends when the later robot arrives: max(own trip, robot 1's trip).
    finish = np.array([max(4.0, 10.0), max(6.0, 0.0)])
    own = np.array([4.0, 6.0])
    expected = pi1 * finish + (1 - pi1) * (own + repair)
    np.testing.assert_allclose(result.G, expected / tau)
    assert result.goal == int(np.argmin(expected))
    np.testing.assert_allclose(result.predictions[1], pi1)


def test_success_risk_by_hand():
    # The risk: E[T | the meeting forms] / tau - 3 ln P(it forms), tau = 10 s (worked at
    # success weight 3, the default until session 50, explicitly).
    planner = Planner(GOALS, MEET, [1.0, 1.0], order=1, temperature=1.0, success_weight=3.0)
    result = planner.plan(0, [[4.0, 0.0], [10.0, 0.0]])
    pi1 = np.exp(-np.array([10.0, 0.0]) / 50.0)
    pi1 /= pi1.sum()
    expected = np.array([10.0, 6.0]) / 10.0 - 3.0 * np.log(pi1)
    np.testing.assert_allclose(result.G, expected)
    assert result.goal == 1


def test_order_zero_heads_for_the_prior_mode():
    planner = Planner(GOALS, MEET, [1.0, 1.0], order=0)
    result = planner.plan(0, [[1.0, 0.0], [1.0, 0.0]], prior=[0.2, 0.8])
    assert result.goal == 1


def test_the_known_set_of_a_teammate_decides_at_order_two():
    # Allocation: robot 0 knows robot 1 keeps only "robot 1 on goal 0".
    planner = Planner(GOALS, [[0, 1], [1, 0]], [1.0, 1.0], order=2)
    positions = [[1.0, 0.0], [9.0, 0.0]]
    assert planner.plan(0, positions).goal == 0  # nearest, as robot 1 is near goal 1
    sets = {(0, 1): np.array([False, True])}
    assert planner.plan(0, positions, sets=sets).goal == 1


def test_third_order_reads_what_a_teammate_thinks_of_oneself():
    # Rendezvous. Robot 0 stands near goal 0 and knows robot 1 knows both meetings, but
    # that robot 1 thinks robot 0 conceives of the meeting at goal 1 only (S_010). At
    # order 2 robot 0 predicts robot 1 from robot 1's set alone: robot 1 expects robot 0
    # at goal 0, its nearest, and goes there. At order 3 robot 0 knows robot 1 expects it
    # at goal 1, so robot 1 goes to goal 1, and so must robot 0.
    sets = {
        (0,): np.array([True, True]),
        (0, 1): np.array([True, True]),
        (0, 1, 0): np.array([False, True]),
    }
    positions = [[1.0, 0.0], [5.0, 0.0]]
    second = Planner(GOALS, MEET, [1.0, 1.0], order=2, evidence=0.5)
    third = Planner(GOALS, MEET, [1.0, 1.0], order=3, evidence=0.5)
    assert second.plan(0, positions, sets=sets).goal == 0
    assert third.plan(0, positions, sets=sets).goal == 1


def test_commitment_and_convention_shift_by_their_nats():
    planner = Planner(GOALS, MEET, [1.0, 1.0], order=1)
    base = planner.plan(0, [[5.0, 0.0], [5.0, 0.0]])
    committed = Planner(GOALS, MEET, [1.0, 1.0], order=1, commitment=2.0)
    shifted = committed.plan(0, [[5.0, 0.0], [5.0, 0.0]], previous=1)
    np.testing.assert_allclose(shifted.G - base.G, [2.0, 0.0], atol=1e-9)
    conventional = Planner(GOALS, MEET, [1.0, 1.0], order=1, convention=1.0)
    out = conventional.plan(0, [[5.0, 0.0], [5.0, 0.0]], prior=[0.25, 0.75])
    plain = planner.plan(0, [[5.0, 0.0], [5.0, 0.0]], prior=[0.25, 0.75])
    np.testing.assert_allclose(out.G - plain.G, [1 - 0.25 / 0.75, 0.0], atol=1e-9)


def test_progress_towards_the_previous_goal_is_charged_in_seconds_over_tau():
    planner = Planner(GOALS, MEET, [1.0, 1.0], order=1)
    base = planner.plan(0, [[5.0, 0.0], [5.0, 0.0]])
    driven = planner.plan(0, [[5.0, 0.0], [5.0, 0.0]], previous=1, progress=3.0)
    # tau = temperature x the goals' spread (10 m) at 1 m/s = 2.5 s: 3 s is 1.2 nats.
    np.testing.assert_allclose(driven.G - base.G, [3.0 / 2.5, 0.0], atol=1e-9)


def test_waiting_pays_when_the_teammate_is_undecided_and_far():
    # Allocation, robot 0 midway and slow to reach either goal; robot 1 far and moving,
    # equally likely to take either goal: guessing risks a long repair; waiting reveals.
    planner = Planner(GOALS, [[0, 1], [1, 0]], [1.0, 1.0], order=1, horizon=3, repair=3.0,
                      evidence=0.2, success_weight=0.0)  # fmt: skip
    result = planner.plan(0, [[5.0, 0.0], [5.0, 30.0]])
    assert result.goal == WAIT
    assert result.wait < result.G.min()
    # A teammate seen standing still reveals nothing by waiting.
    still = planner.plan(0, [[5.0, 0.0], [5.0, 30.0]], moving=[1.0, 0.0])
    assert still.goal != WAIT


def test_motion_evidence_standing_on_a_goal():
    ev = motion_evidence([[10.0, 0.0]], [[10.0, 0.0]], GOALS, [1.0], 1.0, 0.5)
    assert ev[0, 1] == 0.0 and ev[0, 0] == pytest.approx(-2.0)


def test_motion_evidence_per_robot_noise_divides_by_its_variance():
    # Both robots stand on goal 1 at (10, 0) (GOALS: goal 0 at the origin, reach 1 m): the
    # residual under goal 0 is the 1 m step not made, 1 / (2 sigma^2) nats.
    ev = motion_evidence([[10.0, 0.0]] * 2, [[10.0, 0.0]] * 2, GOALS, [1.0, 1.0], 1.0,
                         [0.5, 2.0])  # fmt: skip
    assert ev[:, 0] == pytest.approx([-1 / (2 * 0.25), -1 / (2 * 4.0)])
    assert (ev[:, 1] == 0.0).all()


@settings(max_examples=40, deadline=None)
@given(
    st.integers(2, 3),
    st.integers(2, 4),
    st.integers(0, 3),
    st.integers(0, 10_000),
)
def test_plans_are_distributions_and_respect_the_set(n, m, order, seed):
    rng = np.random.default_rng(seed)
    table = valid_configurations("allocation" if m >= n else "rendezvous", n, m)
    planner = Planner(rng.uniform(0, 20, (m, 2)), table, rng.uniform(0.5, 2, n), order=order)
    keep = rng.random(len(table)) < 0.7
    keep[rng.integers(len(table))] = True
    result = planner.plan(0, rng.uniform(0, 20, (n, 2)), sets={(0,): keep})
    np.testing.assert_allclose(result.predictions.sum(axis=1), 1.0)
    assert np.all(result.predictions >= 0)
    assert result.belief.sum() == pytest.approx(1.0)
    assert np.all(result.belief[~keep] == 0)
    # The robot heads for a goal some configuration it keeps gives it.
    assert result.goal in set(table[keep, 0].tolist())
    assert np.all(np.isinf(result.G[~np.isin(np.arange(m), table[keep, 0])]))


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 3))
def test_relabelling_goals_permutes_the_plan(seed, order):
    rng = np.random.default_rng(seed)
    goals = rng.uniform(0, 20, (3, 2))
    table = valid_configurations("allocation", 2, 3)
    positions = rng.uniform(0, 20, (2, 2))
    perm = rng.permutation(3)
    inverse = np.argsort(perm)
    a = Planner(goals, table, [1.0, 1.0], order=order).plan(0, positions)
    b = Planner(goals[perm], inverse[table], [1.0, 1.0], order=order).plan(0, positions)
    np.testing.assert_allclose(b.G, a.G[perm], rtol=1e-9)


def test_bad_arguments_are_refused():
    with pytest.raises(InvalidArgumentError):
        Planner(GOALS, MEET, [1.0, 0.0])
    with pytest.raises(InvalidArgumentError):
        Planner(GOALS, MEET, [1.0, 1.0], temperature=-1)
    with pytest.raises(InvalidArgumentError):
        Planner(GOALS, MEET, [1.0, 1.0]).plan(0, [[np.nan, 0.0], [0.0, 0.0]])
    with pytest.raises(InvalidArgumentError):
        Planner(GOALS, MEET, [1.0, 1.0]).plan(0, [[0.0, 0.0], [0.0, 0.0]], prior=[-1, 2])


def _allocation_of_three():
    goals = np.array([[0.0, 0.0], [30.0, 0.0], [15.0, 30.0]])
    return goals, valid_configurations("allocation", 3, 3)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_an_unseen_teammate_is_the_mean_of_its_predictions_from_the_draws(order):
    goals, rows = _allocation_of_three()
    planner = Planner(goals, rows, [1.0, 1.0, 1.0], order=order)
    placeholder = np.array([[2.0, 1.0], [15.0, 15.0], [15.0, 15.0]])
    places = np.full((3, 3, 2), np.nan)
    places[:, 1] = [[3.0, 2.0], [25.0, 5.0], [14.0, 27.0]]
    places[:, 2] = [[28.0, 1.0], [16.0, 25.0], [5.0, 9.0]]
    plan = planner.plan(0, placeholder, unseen=places)
    # Recomputed through the public API: the plan from each draw's positions, averaged.
    draws = []
    for draw in places:
        moved = placeholder.copy()
        moved[1:] = draw[1:]
        draws.append(planner.plan(0, moved).predictions)
    np.testing.assert_allclose(plan.predictions[1:], np.mean(draws, axis=0)[1:], atol=1e-12)


def test_two_unseen_teammates_at_one_placeholder_are_no_longer_one_prediction():
    goals, rows = _allocation_of_three()
    planner = Planner(goals, rows, [1.0, 1.0, 1.0], order=2)
    placeholder = np.array([[2.0, 1.0], [15.0, 15.0], [15.0, 15.0]])
    blind = planner.plan(0, placeholder).predictions
    np.testing.assert_allclose(blind[1], blind[2])  # the failure: both at one goal
    places = np.full((4, 3, 2), np.nan)
    places[:, 1:] = np.array([[[3, 2], [25, 5]], [[25, 5], [14, 27]], [[14, 27], [3, 2]],
                              [[20, 20], [8, 22]]], dtype=float)  # fmt: skip
    spread = planner.plan(0, placeholder, unseen=places).predictions
    assert np.abs(spread[1] - spread[2]).max() > 0.1
    np.testing.assert_allclose(spread.sum(axis=1), 1.0)


def test_unseen_places_of_a_seen_robot_or_the_same_place_change_nothing():
    goals, rows = _allocation_of_three()
    planner = Planner(goals, rows, [1.0, 1.0, 1.0], order=3)
    positions = np.array([[2.0, 1.0], [25.0, 5.0], [14.0, 27.0]])
    moves = np.zeros((3, 3))
    moves[1] = [-6.0, 0.0, -6.0]  # r1 was seen heading for goal 1: read before the draws
    base = planner.plan(0, positions, evidence=moves)
    nobody = np.full((5, 3, 2), np.nan)
    same = np.repeat(positions[None], 5, axis=0)
    same[:, 0] = np.nan
    for places in (nobody, same):
        again = planner.plan(0, positions, evidence=moves, unseen=places)
        np.testing.assert_allclose(again.G, base.G)
        np.testing.assert_allclose(again.predictions, base.predictions)
    with pytest.raises(InvalidArgumentError, match="shape"):
        planner.plan(0, positions, unseen=np.zeros((2, 3)))
