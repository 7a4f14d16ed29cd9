"""The collaborative planner (epistemica.aif.task_planning): expected completion times worked
by hand and by enumeration, the convention, and laws of the plans."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica import InvalidArgumentError
from epistemica.aif.task_context import TaskContext
from epistemica.aif.task_planning import Fetch, TaskPlanner, completion_times, convention


def _enumerated(arrivals, presence, need, fail, credit, timed=False, quorum=1):
    """E[T] of one task by summing over every subset of robots that come."""
    total = 0.0
    for came in itertools.product([False, True], repeat=len(arrivals)):
        weight = np.prod([p if c else 1 - p for p, c in zip(presence, came, strict=True)])
        times = sorted(a for a, c in zip(arrivals, came, strict=True) if c)
        if len(times) >= need:
            total += weight * times[need - 1]
        else:
            shares = [max(1 - a / fail, 0.0) if timed else 1.0 for a in times]
            earned = sum(shares) if len(times) >= quorum else 0.0
            total += weight * fail * (1 - credit * earned / need)
    return total


def test_completion_time_of_one_task_by_hand():
    # Robot 0 surely comes (4 steps), robots 1 (7) and 2 (9) each with probability 1/2; the
    # task needs 2: done at 7 if robot 1 comes, else at 9 if robot 2 does, else it fails.
    got = completion_times([[4.0], [7.0], [9.0]], [[1.0], [0.5], [0.5]], [2], [100.0])
    assert got.tolist() == pytest.approx([0.5 * 7 + 0.25 * 9 + 0.25 * 100])
    # With full credit, the failing quarter has one robot of two: half the cost.
    got = completion_times([[4.0], [7.0], [9.0]], [[1.0], [0.5], [0.5]], [2], [100.0], 1.0)
    assert got.tolist() == pytest.approx([0.5 * 7 + 0.25 * 9 + 0.25 * 50])


@settings(max_examples=100, deadline=None)
@given(
    st.integers(1, 5).flatmap(
        lambda r: st.tuples(
            st.lists(st.floats(0, 120), min_size=r, max_size=r),
            st.lists(st.floats(0, 1), min_size=r, max_size=r),
            st.integers(1, r),
            st.floats(0, 1),
            st.booleans(),
            st.integers(1, 4),
        )
    )
)
def test_completion_times_match_enumeration(case):
    # Timed, arrivals past the fail cost (80) earn nothing; fewer than the quorum nothing.
    arrivals, presence, need, credit, timed, quorum = case
    got = completion_times(np.array(arrivals)[:, None], np.array(presence)[:, None], [need],
                           [80.0], credit, timed=timed, quorum=quorum)  # fmt: skip
    want = _enumerated(arrivals, presence, need, 80.0, credit, timed=timed, quorum=quorum)
    assert got[0] == pytest.approx(want, abs=1e-9)


def test_timed_credit_ranks_fetches_by_when_the_helper_comes():
    # A task needing 4 that only robot 0 knows of; fetching robot 1 brings both by step
    # 12, robot 2 by step 30. Two of four come either way: untimed, each fetch earns two
    # shares of credit (50 of 100) and they tie; timed, a share is worth 1 - a / 100.
    sets, unknown = {(0,): [True], (0, 1): [False], (0, 2): [False]}, {(0, 1): 1, (0, 2): 1}
    fetches = [Fetch(0, 1, 12.0, 12.0, 1.0), Fetch(0, 2, 30.0, 30.0, 1.0)]
    arrivals = [[3.0], [20.0], [25.0]]
    untimed = TaskPlanner([4], order=2, temperature=1.0, fail=[100.0], credit=1.0)
    G = untimed.plan(0, arrivals, sets, unknown, fetches).G
    assert G[2] == pytest.approx(G[3]) == pytest.approx(-50.0)
    timed = TaskPlanner([4], order=2, temperature=1.0, fail=[100.0], credit=1.0, timed=True)
    plan = timed.plan(0, arrivals, sets, unknown, fetches)
    assert plan.G[2:].tolist() == pytest.approx([-(100 - 12) / 2, -(100 - 30) / 2])
    assert (plan.kind, plan.helper) == ("fetch", 1)


def test_coming_later_anyway_is_the_baseline_of_an_option():
    # Robots 0 and 1 (4 and 10 steps away) both go to a task needing both (the convention).
    # Never coming otherwise, robot 0 going saves the whole fail cost less 10 steps; coming
    # 30 steps later otherwise (at step 34), it saves 24 steps.
    arrivals, sets = [[4.0], [10.0]], {(0,): [True]}
    never = TaskPlanner([2], order=1, temperature=1.0, fail=[100.0])
    assert never.plan(0, arrivals, sets).G[0] == pytest.approx(10.0 - 100.0)
    later = TaskPlanner([2], order=1, temperature=1.0, fail=[100.0], later=30.0)
    assert later.plan(0, arrivals, sets).G[0] == pytest.approx(10.0 - 34.0)
    # Waiting alone at a task needing 3 that nobody else comes to (timed credit): worth
    # one share of the 30 steps by which it is there sooner, not a share of the fail cost.
    alone = TaskPlanner([3], order=1, temperature=1.0, fail=[100.0], credit=1.0, timed=True,
                        later=30.0)  # fmt: skip
    sets = {(0,): [True], (0, 1): [False]}
    G = alone.plan(0, [[0.0], [10.0]], sets, {(0, 1): 1}).G
    assert G[0] == pytest.approx(-30.0 / 3)


def _enumerated_pooled(arrivals, presence, free, brought, need, fail):
    """E[T] of one task over every robot's state (comes / free / elsewhere): credit 1 per
    robot that came and was brought, counted only when enough of the rest are free."""
    total = 0.0
    states = [(p, f, 1 - p - f) for p, f in zip(presence, free, strict=True)]
    for state in itertools.product(range(3), repeat=len(arrivals)):
        weight = np.prod([s[k] for s, k in zip(states, state, strict=True)])
        came = [k for k, x in enumerate(state) if x == 0]
        times = sorted(arrivals[k] for k in came)
        if len(times) >= need:
            total += weight * times[need - 1]
            continue
        earned = sum(brought[k] for k in came) if len(came) + state.count(1) >= need else 0
        total += weight * fail * (1 - earned / need)
    return total


@settings(max_examples=100, deadline=None)
@given(
    st.integers(1, 4).flatmap(
        lambda r: st.tuples(
            st.lists(st.floats(0, 120), min_size=r, max_size=r),
            st.lists(st.floats(0, 1), min_size=r, max_size=r),
            st.lists(st.floats(0, 1), min_size=r, max_size=r),
            st.lists(st.booleans(), min_size=r, max_size=r),
            st.integers(1, r),
        )
    )
)
def test_pooled_and_brought_credit_match_enumeration(case):
    arrivals, presence, share, brought, need = case
    free = [s * (1 - p) for s, p in zip(share, presence, strict=True)]
    column = lambda v: np.array(v, dtype=float)[:, None]  # noqa: E731
    got = completion_times(column(arrivals), column(presence), [need], [80.0], 1.0,
                           brought=column(brought), free=column(free))  # fmt: skip
    want = _enumerated_pooled(arrivals, presence, free, brought, need, 80.0)
    assert got[0] == pytest.approx(want, abs=1e-9)


def test_waiting_for_teammates_predicted_elsewhere_is_worth_nothing_when_pooled():
    # Robot 0 alone at a task needing 3 (arrival 0). Its two teammates are free (exploring,
    # to be brought) or busy elsewhere: with both free it keeps its third of the credit.
    at, coming = [[0.0], [30.0], [30.0]], [[1.0], [0.0], [0.0]]
    both = completion_times(at, coming, [3], [90.0], 1.0, free=[[0.0], [1.0], [1.0]])
    one = completion_times(at, coming, [3], [90.0], 1.0, free=[[0.0], [1.0], [0.0]])
    assert both.tolist() == pytest.approx([60.0]) and one.tolist() == pytest.approx([90.0])


def test_rendezvous_values_coming_by_completion_and_bringing_by_credit():
    # A task needing 3 that only robot 0 knows of. Coming alone completes nothing: worth 0
    # (with credit: a third of the fail cost). Fetching robot 1 (found surely) brings one
    # knower: a third of the fail cost, not the two thirds of robot and helper.
    sets, unknown = {(0,): [True], (0, 1): [False], (0, 2): [False]}, {(0, 1): 1, (0, 2): 1}
    arrivals, fetch = [[3.0], [20.0], [25.0]], [Fetch(0, 1, 12.0, 12.0, 1.0)]
    credit = TaskPlanner([3], order=2, temperature=1.0, fail=[90.0], credit=1.0)
    meet = TaskPlanner([3], order=2, temperature=1.0, fail=[90.0], credit=1.0, rendezvous=True)
    assert credit.plan(0, arrivals, sets, unknown, fetch).G[[0, 2]] == pytest.approx([-30, -60])
    assert meet.plan(0, arrivals, sets, unknown, fetch).G[[0, 2]] == pytest.approx([0, -30])


def test_a_fetch_is_charged_what_its_helper_leaves_undone():
    # Robot 1 and robot 2 know of task 0 (needs 2) and are both sent there (the convention);
    # robot 0 may fetch robot 1 for task 1 (needs 2, both there by step 12). Taking robot 1
    # away leaves robot 2 alone at task 0: done at step 1 -> 100 less robot 2's half.
    sets = {(0,): [True, True], (0, 1): [True, False], (0, 2): [True, False]}
    arrivals, fetch = [[30.0, 3.0], [1.0, 20.0], [1.0, 25.0]], [Fetch(1, 1, 12.0, 12.0, 1.0)]
    kw = dict(order=2, temperature=1.0, fail=[100.0, 100.0], credit=1.0)
    alone = TaskPlanner([2, 2], **kw).plan(0, arrivals, sets, {}, fetch).G[3]
    whole = TaskPlanner([2, 2], mission=True, **kw).plan(0, arrivals, sets, {}, fetch).G[3]
    assert alone == pytest.approx(12.0 - 100.0)
    assert whole - alone == pytest.approx((100.0 - 50.0) - 1.0)


def test_a_robot_that_cannot_arrive_never_comes():
    got = completion_times([[3.0], [np.inf]], [[1.0], [1.0]], [2], [60.0])
    assert got.tolist() == [60.0]


def test_the_convention_sends_the_soonest_coalition_first():
    # Task 1 assembles by step 3 (robots 1 and 2), task 0 only by step 5 (robots 0 and 1):
    # task 1 takes robots 1 and 2; task 0 is left with one free knower, robot 0.
    got = convention([[5, 9], [2, 3], [9, 1]], [[1, 1], [1, 1], [0, 1]], [2, 2])
    assert got.tolist() == [-1, 1, 1]
    # Robot 2 does not know of task 1: task 0 goes first, robot 2 explores.
    got = convention([[5, 9], [2, 3], [9, 1]], [[1, 1], [1, 1], [0, 0]], [2, 2])
    assert got.tolist() == [0, 0, -1]


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 6), st.integers(1, 4))
def test_the_convention_fills_a_task_or_leaves_it(seed, n, m):
    rng = np.random.default_rng(seed)
    arrivals = rng.uniform(0, 30, (n, m))
    knowers = rng.random((n, m)) < 0.7
    needs = rng.integers(1, n + 1, m)
    got = convention(arrivals, knowers, needs)
    for t in range(m):
        sent = np.flatnonzero(got == t)
        assert sent.size in (0, needs[t])
        assert knowers[sent, t].all()
    # a task left with enough free knowers would have been filled
    free = got < 0
    for t in np.flatnonzero(np.bincount(got[got >= 0], minlength=m) == 0):
        assert (knowers[:, t] & free).sum() < needs[t]


def test_a_plan_of_three_robots_worked_by_hand():
    # One task needing 2; robots 5, 8 and 12 steps away, everyone knows of it (order 1,
    # teammates predicted by the convention: robots 0 and 1 go, robot 2 explores).
    arrivals = [[5.0], [8.0], [12.0]]
    planner = TaskPlanner([2], order=1, temperature=1.0, fail=[100.0], credit=1.0)
    plan = planner.plan(0, arrivals, {(0,): [True]})
    # With it: done at 8. Without it: robot 1 alone, half of the fail cost (credit 1).
    assert plan.kind == "task" and plan.task == 0
    assert plan.G[0] == pytest.approx(8.0 - 50.0)
    np.testing.assert_allclose(plan.predictions[1], [1.0, 0.0])
    np.testing.assert_allclose(plan.predictions[2], [0.0, 1.0])
    # Robot 2 expects robots 0 and 1 there by step 8: coming saves nothing, it explores.
    plan = planner.plan(2, arrivals, {(2,): [True]})
    assert plan.kind == "explore" and plan.G[0] == pytest.approx(0.0)


def test_exploring_saves_a_share_of_the_unknown_tasks():
    planner = TaskPlanner([2, 2], order=1, temperature=2.0, fail=[40.0, 80.0], explore=0.5)
    plan = planner.plan(0, [[5.0, np.inf], [8.0, np.inf]], {(0,): [True, False]}, {(0,): 1})
    assert plan.G[2] == pytest.approx(-0.5 * 60.0 * 1 / 2 / 2.0)  # nats: / tau
    assert np.isinf(plan.G[1])  # not open to it


def test_a_teammate_that_does_not_know_is_fetched_at_order_two():
    # Robot 0 knows robot 1 does not know of the task: robot 1 explores, going alone
    # saves half the fail cost (credit 1), fetching it (both there at step 12, found
    # with probability 0.9) saves 100 - (0.9 * 12 + 0.1 * 50).
    planner = TaskPlanner([2], order=2, temperature=1.0, fail=[100.0], credit=1.0)
    sets = {(0,): [True], (0, 1): [False]}
    plan = planner.plan(0, [[5.0], [10.0]], sets, {(0, 1): 1}, [Fetch(0, 1, 12.0, 12.0, 0.9)])
    np.testing.assert_allclose(plan.predictions[1], [0.0, 1.0])
    assert plan.G[0] == pytest.approx(50.0 - 100.0)
    assert plan.G[2] == pytest.approx(0.9 * 12 + 0.1 * 50 - 100.0)
    assert (plan.kind, plan.task, plan.helper) == ("fetch", 0, 1)
    # Taking robot 1 to know of it (its chain absent: it keeps robot 0's set), both go.
    plan = planner.plan(0, [[5.0], [10.0]], {(0,): [True]})
    assert plan.kind == "task" and plan.G[0] == pytest.approx(10.0 - 50.0)


@pytest.mark.parametrize("recruit", [False, True])
def test_the_convention_weighs_a_fetch_as_exploring_when_recruiting(recruit):
    # The fetch of the test above, with the convention weighing 1: the convention has
    # robot 0 explore (robot 1 is not a knower), so its prior is 0.95 + 0.05 / 3 on
    # exploring and 0.05 / 3 on the task and on the fetch, unless recruiting gives the
    # fetch exploring's prior.
    sets, unknown = {(0,): [True], (0, 1): [False]}, {(0, 1): 1}
    fetch = [Fetch(0, 1, 12.0, 12.0, 0.9)]
    raw = TaskPlanner([2], order=2, temperature=1.0, fail=[100.0], credit=1.0)
    weighed = TaskPlanner([2], order=2, temperature=1.0, fail=[100.0], credit=1.0,
                          convention=1.0, recruit=recruit)  # fmt: skip
    base = raw.plan(0, [[5.0], [10.0]], sets, unknown, fetch).G
    G = weighed.plan(0, [[5.0], [10.0]], sets, unknown, fetch).G
    rest, explore = 0.05 / 3, 0.95 + 0.05 / 3
    expected = base - np.log([rest, explore, explore if recruit else rest])
    np.testing.assert_allclose(G, expected)


def test_commitment_keeps_the_previous_option():
    planner = TaskPlanner([1, 1], order=1, temperature=1.0, fail=[50.0, 50.0], commitment=3.0)
    # One robot, two tasks it does alone: 5 or 6 steps of the 50 of failing saved.
    sets = {(0,): [True, True]}
    assert planner.plan(0, [[5.0, 6.0]], sets).task == 0
    assert planner.plan(0, [[5.0, 6.0]], sets, previous=1).task == 1  # 3 nats > 1 step
    assert planner.plan(0, [[5.0, 9.0]], sets, previous=1).task == 0  # 3 nats < 4 steps


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 5), st.integers(1, 3), st.integers(0, 3))
def test_predictions_are_distributions_and_scores_finite_on_open_tasks(seed, n, m, order):
    rng = np.random.default_rng(seed)
    arrivals = rng.uniform(0, 40, (n, m))
    needs = rng.integers(1, n + 1, m)
    sets = {(0,): rng.random(m) < 0.7}
    for j in range(1, n):
        sets[(0, j)] = rng.random(m) < 0.5
        for h in range(n):
            if h != j:
                sets[(0, j, h)] = sets[(0, j)] & (rng.random(m) < 0.7)
    unknown = {chain: int(rng.integers(0, 3)) for chain in sets}
    planner = TaskPlanner(needs, order=order, temperature=3.0, fail=60.0, explore=0.3,
                          convention=1.0, credit=0.5)  # fmt: skip
    plan = planner.plan(0, arrivals, sets, unknown)
    np.testing.assert_allclose(plan.predictions.sum(axis=1), 1.0)
    assert (plan.predictions >= 0).all()
    if order >= 1:
        assert np.isfinite(plan.G[:m][sets[(0,)]]).all()
        assert np.isinf(plan.G[:m][~sets[(0,)]]).all()
        assert np.isfinite(plan.G[m])
    assert np.isfinite(plan.G[plan.option])


def test_bad_arguments_are_refused():
    planner = TaskPlanner([2], order=1)
    with pytest.raises(InvalidArgumentError):
        planner.plan(0, [[1.0, 2.0]], {(0,): [True]})
    with pytest.raises(InvalidArgumentError):
        planner.plan(0, [[1.0], [2.0]], {(1,): [True]})
    with pytest.raises(InvalidArgumentError):
        TaskPlanner([0])
    with pytest.raises(InvalidArgumentError):
        TaskPlanner([2], explore=-1.0)
    with pytest.raises(InvalidArgumentError):
        TaskPlanner([2], quorum=0)
    with pytest.raises(InvalidArgumentError):
        TaskPlanner([2], later=0.0)


def _recruiting():
    """Task 0 needs 3; robots 0 and 1 know of it, robot 2 does not, and robot 0 knows that
    robot 1 knows robot 2 does not. Robot 1 fetching robot 2 brings both by step 20."""
    sets = {(0,): [True], (0, 1): [True], (0, 2): [False], (0, 1, 0): [True],
            (0, 1, 2): [False], (0, 2, 0): [False], (0, 2, 1): [False]}  # fmt: skip
    meetings = np.full((3, 3, 1), np.inf)
    meetings[1, 2, 0] = 20.0
    return [[5.0], [6.0], [8.0]], sets, meetings


def test_a_teammates_predicted_fetch_brings_the_pair_at_the_meeting():
    arrivals, sets, meetings = _recruiting()
    planner = TaskPlanner([3], order=3, temperature=5.0, fail=[100.0], fetchers=True)
    context = TaskContext(planner, np.array(arrivals), sets, {}, meetings)
    own = context.costs((0,), 3)
    q, when = context.fetching((0, 1), 2)
    assert 0 < q[0] < 1 and when[0] == 20.0
    pick = [context.choice((0, j), 2)[0] for j in (1, 2)]
    assert pick[1] == 0.0  # robot 2 does not know of the task
    np.testing.assert_allclose(context.choice((0, 1), 2).sum(), 1.0 - q[0])
    # Robot 0's option, by enumerating who comes: robot 1 by itself, robot 2, the pair.
    times = [5.0, 6.0, 8.0, 20.0, 20.0]
    going = _enumerated(times, [1.0, pick[0], pick[1], q[0], q[0]], 3, 100.0, 0.0)
    staying = _enumerated(times, [0.0, pick[0], pick[1], q[0], q[0]], 3, 100.0, 0.0)
    assert own[0] == pytest.approx(going - staying)


def test_with_teammates_fetches_predicted_the_knower_goes_to_the_task():
    # All or nothing, a task needing three that only two know of is worth nothing to
    # robot 0 unless robot 1 is predicted to bring robot 2.
    arrivals, sets, meetings = _recruiting()
    kinds = {}
    for fetchers in (False, True):
        planner = TaskPlanner([3], order=3, temperature=5.0, fail=[100.0], fetchers=fetchers)
        kinds[fetchers] = planner.plan(0, arrivals, sets, {(0, 2): 1}, meetings=meetings).kind
    assert kinds == {False: "explore", True: "task"}


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 4), st.integers(1, 3), st.integers(1, 3))
def test_no_possible_fetch_leaves_the_plan_as_without_fetchers(seed, n, m, order):
    rng = np.random.default_rng(seed)
    arrivals = rng.uniform(0, 40, (n, m))
    sets = {(0,): rng.random(m) < 0.7}
    for j in range(1, n):
        sets[(0, j)] = rng.random(m) < 0.5
        for h in range(n):
            if h != j:
                sets[(0, j, h)] = rng.random(m) < 0.5
    needs, never = rng.integers(1, n + 1, m), np.full((n, n, m), np.inf)
    plans = [
        TaskPlanner(needs, order=order, temperature=3.0, fail=60.0, credit=0.5,
                    fetchers=fetchers).plan(0, arrivals, sets, meetings=never)
        for fetchers in (False, True)
    ]  # fmt: skip
    np.testing.assert_allclose(plans[1].G, plans[0].G)
    np.testing.assert_allclose(plans[1].predictions, plans[0].predictions)


def test_meetings_of_the_wrong_shape_are_refused():
    with pytest.raises(InvalidArgumentError):
        TaskPlanner([2], fetchers=True).plan(0, [[1.0], [2.0]], {(0,): [True]},
                                             meetings=np.zeros((2, 2, 2)))  # fmt: skip


@pytest.mark.parametrize("knowers", [False, True])
def test_with_knowers_waiting_alone_at_a_task_too_few_know_of_saves_nothing(knowers):
    # One task needing 2, robot 0 at 5 steps, robot 1 at 10; fail 100, full credit.
    # Robot 1 does not know of it (order 2 reads the chain (0, 1)): alone, robot 0 earns
    # half the fail cost as credit (G = -50), unless too few knowers earn none (G = 0).
    # Fetching robot 1 (both there at 12, found with 0.9): 0.9 * 12 + 0.1 * 50 = 15.8
    # against 100 either way (without the fetch nobody comes): -84.2.
    planner = TaskPlanner([2], order=2, temperature=1.0, fail=[100.0], credit=1.0,
                          knowers=knowers)  # fmt: skip
    sets = {(0,): [True], (0, 1): [False]}
    plan = planner.plan(0, [[5.0], [10.0]], sets, {(0, 1): 1}, [Fetch(0, 1, 12.0, 12.0, 0.9)])
    assert plan.G[0] == pytest.approx(0.0 if knowers else -50.0)
    assert plan.G[2] == pytest.approx(-84.2)
    # When robot 1 knows too, two robots know and the credit counts either way:
    # robot 1 comes alone (credit 50) unless robot 0 comes too (done at 10): 50 - 10.
    both = planner.plan(0, [[5.0], [10.0]], {(0,): [True], (0, 1): [True]})
    assert both.G[0] == pytest.approx(-40.0)


@pytest.mark.parametrize("waits", [False, True])
def test_a_teammate_seen_waiting_is_predicted_at_its_task(waits):
    # Tasks 0 and 1 each need 2, both robots know both; robot 0 is 4 and 9 steps away,
    # robot 1 3 and 0 (it stands at task 1). The convention sends both to task 0 (ready at
    # step 4, against 9), so robot 1 is predicted there: task 0 saves 100 - 4 = 96 and task
    # 1 nothing. Seen waiting at task 1, robot 1 is predicted there: task 1 saves
    # 100 - 9 = 91, task 0 nothing (robot 0 alone there fails either way).
    planner = TaskPlanner([2, 2], order=1, temperature=1.0, fail=[100.0, 100.0])
    sets = {(0,): [True, True], (0, 1): [True, True]}
    plan = planner.plan(0, [[4.0, 9.0], [3.0, 0.0]], sets, waiting={1: 1} if waits else None)
    assert plan.G.tolist() == ([0.0, -91.0, 0.0] if waits else [-96.0, 0.0, 0.0])
    assert (plan.kind, plan.task) == (("task", 1) if waits else ("task", 0))
    assert plan.predictions[1].tolist() == ([0.0, 1.0, 0.0] if waits else [1.0, 0.0, 0.0])


def test_waiting_must_name_teammates_and_tasks():
    planner = TaskPlanner([2], order=1)
    for bad in ({0: 0}, {2: 0}, {1: 1}, {-1: 0}):
        with pytest.raises(InvalidArgumentError, match="waiting"):
            planner.plan(0, [[1.0], [2.0]], {(0,): [True]}, waiting=bad)


@pytest.mark.parametrize("stands", [None, {1: 0}, {1: 1}])
def test_a_fetch_of_a_teammate_standing_at_a_task_is_charged_what_that_task_loses(stands):
    # Tasks 0 and 1 each need 2 (fail 100, credit 1). Robot 1 is seen waiting at task 0
    # (predicted there) and knows nothing of task 1; fetching it, both reach task 1 at step
    # 10: 10 against 100 with nobody there, -90. Robot 1 alone at task 0 earns half the
    # cost back (100 - 50); taken from it, task 0 loses those 50: the fetch is charged 50
    # when robot 1 is seen standing at task 0, and nothing when at task 1, the fetch's own.
    planner = TaskPlanner([2, 2], order=1, temperature=1.0, fail=[100.0, 100.0], credit=1.0)
    sets = {(0,): [True, True], (0, 1): [True, False]}
    plan = planner.plan(0, [[4.0, 9.0], [0.0, 20.0]], sets, fetches=[Fetch(1, 1, 10.0, 10.0, 1.0)],
                        waiting={1: 0}, stands=stands)  # fmt: skip
    assert plan.G[3] == pytest.approx(-40.0 if stands == {1: 0} else -90.0)


def test_stands_must_name_teammates_and_tasks():
    planner = TaskPlanner([2], order=1)
    for bad in ({0: 0}, {2: 0}, {1: 1}):
        with pytest.raises(InvalidArgumentError, match="stands"):
            planner.plan(0, [[1.0], [2.0]], {(0,): [True]}, stands=bad)
