"""``plan_claim = 3``: the team type's moves are read against the yielding planner a claim
assumes (:func:`epistemica.sim.policies.planning.yielded`; aif.md §6g, session 51)."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.aif.teammates import TYPE_PRIOR, TYPES, motion_log_likelihood, update_types
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import yielded

GOALS = np.array([[0.0, 0.0], [0.0, 9.0], [9.0, 9.0]])
ALLOCATIONS = np.array([[0, 1], [1, 0], [0, 2], [2, 0], [1, 2], [2, 1]])


def test_a_later_teammate_is_conditioned_off_the_robots_goal():
    # Robot 0 is 1 m from goal 0, robot 1 3 m (unit speeds): robot 1 is later and yields.
    planned = np.array([[1.0, 0.0, 0.0], [0.8, 0.15, 0.05]])
    at = np.array([[1.0, 0.0], [3.0, 0.0]])
    out = yielded(planned, 0, 0, at, GOALS, np.ones(2), ALLOCATIONS)
    assert np.allclose(out[1], [0.0, 0.15 / 0.2, 0.05 / 0.2])
    assert np.array_equal(out[0], planned[0])
    # Robot 1 first (robot 0 now 5 m away): no claim, the plan's prediction stands.
    early = yielded(planned, 0, 0, np.array([[5.0, 0.0], [3.0, 0.0]]), GOALS, np.ones(2),
                    ALLOCATIONS)  # fmt: skip
    assert np.array_equal(early, planned)
    # A faster teammate arrives first although it is farther: 3 m at 4 m/s < 1 s.
    fast = yielded(planned, 0, 0, at, GOALS, np.array([1.0, 4.0]), ALLOCATIONS)
    assert np.array_equal(fast, planned)


def test_a_goal_shared_in_some_configuration_is_not_contested():
    rendezvous = np.array([[0, 0], [1, 1], [2, 2]])
    planned = np.array([[1.0, 0.0, 0.0], [0.8, 0.15, 0.05]])
    at = np.array([[1.0, 0.0], [3.0, 0.0]])
    assert np.array_equal(yielded(planned, 0, 0, at, GOALS, np.ones(2), rendezvous), planned)


def test_waiting_beside_the_robots_goal_reads_as_stationary_not_as_a_yielding_planner():
    # allocation_adhoc_stationary_silent_5 seed 1001 in small: robot 1 waits 0.5 m from goal
    # 0, which robot 0 holds. As the plan predicts it (goal 0, 0.9), its wait is close to a
    # planner's last half step; as a yielding planner it should step 1 m away.
    planned = np.array([[1.0, 0.0, 0.0], [0.9, 0.05, 0.05]])
    at = np.array([[0.0, 0.0], [0.5, 0.0]])
    still = at[1:]
    team = {}
    for read in (False, True):
        row = yielded(planned, 0, 0, at, GOALS, np.ones(2), ALLOCATIONS) if read else planned
        probs = np.full((1, len(TYPES), 3), 1.0 / 3)
        probs[0, TYPES.index("team")] = row[1]
        ll = motion_log_likelihood(still, still, probs, GOALS, np.ones(1), 0.5)
        team[read] = np.exp(update_types(np.log(TYPE_PRIOR)[None], ll, 0.0))[0, 0]
    # By hand (sigma 0.5): a miss of 0.5 m costs 0.5 nats, of 1 m 2 nats; still costs 0.
    near, far = np.exp(-0.5), np.exp(-2.0)
    greedy = convention = (near + 2 * far) / 3  # uniform rows here
    for read, t in ((False, 0.9 * near + 0.1 * far), (True, far)):
        expected = 0.5 * t / (0.5 * t + (greedy + convention + 1.0) / 6)
        assert np.isclose(team[read], expected)
    assert team[False] > 0.5 > 0.25 > team[True]  # 0.51 against 0.20


def test_plan_claim_takes_three_and_is_six_by_default():
    assert ActiveParameters().plan_claim == 6  # session 52
    assert ActiveParameters(plan_claim=3).plan_claim == 3
    with pytest.raises(InvalidArgumentError, match="plan_claim"):
        ActiveParameters(plan_claim=7)
