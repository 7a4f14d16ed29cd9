"""Anticipating teammates from what they can conceive of (sim/policies/anticipation.py).

Laws of :func:`anticipated_prior` over random configuration tables, sets and priors, a
hand-worked three-robot case, and the closed loop: on the mission where one robot alone
knows the cheapest meeting place, anticipation is what lets the team meet.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif.configurations import valid_configurations
from epistemica.mission import parse_mission
from epistemica.sim import simulate
from epistemica.sim.policies.anticipation import anticipated_prior, goal_distribution


@st.composite
def cases(draw):
    """A table, a positive team prior, the robot's set and one set per teammate."""
    mission = draw(st.sampled_from(["rendezvous", "allocation"]))
    n = draw(st.integers(2, 3))
    m = draw(st.integers(n, 4))
    table = valid_configurations(mission, n, m)
    k = len(table)
    base = np.array(draw(st.lists(st.floats(0.01, 1.0), min_size=k, max_size=k)))
    own = np.array(draw(st.lists(st.booleans(), min_size=k, max_size=k)))
    own[draw(st.integers(0, k - 1))] = True
    theirs = {
        j: np.array(draw(st.lists(st.booleans(), min_size=k, max_size=k))) for j in range(1, n)
    }
    return table, base / base.sum(), own, theirs


@settings(max_examples=200, deadline=None)
@given(cases())
def test_a_distribution_on_the_robots_own_set(case):
    table, base, own, theirs = case
    p = anticipated_prior(table, base, 0, own, theirs)
    assert np.isclose(p.sum(), 1.0) and (p >= 0).all()
    assert (p[~own] == 0).all()


@settings(max_examples=200, deadline=None)
@given(cases())
def test_nobody_to_anticipate_leaves_the_prior_on_the_own_set(case):
    table, base, own, _ = case
    expected = np.where(own, base, 0.0) / base[own].sum()
    assert np.allclose(anticipated_prior(table, base, 0, own, {}), expected)


@settings(max_examples=200, deadline=None)
@given(cases())
def test_a_teammate_is_never_expected_where_it_cannot_conceive_to_go(case):
    # A goal teammate j keeps no configuration for cannot be where it heads: unless no
    # configuration of the robot's set survives the predictions (then the fallback), or
    # j keeps nothing at all (a chain with no set says nothing about j).
    table, base, own, theirs = case
    p = anticipated_prior(table, base, 0, own, theirs)
    for j, mask in theirs.items():
        if not mask.any():
            continue
        conceivable = np.unique(table[mask, j])
        outside = ~np.isin(table[:, j], conceivable)
        fallback = np.allclose(p, np.where(own, base, 0.0) / base[own].sum())
        assert fallback or (p[outside] == 0).all()


def test_a_hand_worked_three_robot_meeting():
    # Rendezvous, 3 robots, goals 0, 1, 2 (configurations: everyone at g). Team prior
    # 0.2, 0.5, 0.3. Robot 0 knows all three; robot 1 knows goals 0 and 2 only; robot 2
    # knows all. Robot 1's prediction: over its set {0, 2} the prior gives 0.2 / 0.5 and
    # 0.3 / 0.5, so pi_1 = (0.4, 0, 0.6); robot 2 keeps what robot 0 keeps and is not
    # anticipated. Robot 0's prior is base * pi_1: (0.08, 0, 0.18) / 0.26.
    table = valid_configurations("rendezvous", 3, 3)
    order = np.argsort(table[:, 0])
    table = table[order]
    base = np.array([0.2, 0.5, 0.3])
    own = np.ones(3, dtype=bool)
    robot1 = table[:, 0] != 1
    p = anticipated_prior(table, base, 0, own, {1: robot1})
    assert np.allclose(p, np.array([0.08, 0.0, 0.18]) / 0.26)
    assert np.allclose(goal_distribution(table, np.where(robot1, base, 0), 1, 3), [0.4, 0, 0.6])


PRIVATE_GOAL = """mission rendezvous
workspace 30
robot r1..r3: random at random
goal g1..g3 at random
goal g4 at (15, 15)
knows r1: g1, g2, g3, g4
knows r2, r3: g1, g2, g3
sensing model paper noise 0.5 range 6 discovery 3
event settle seen by nearby
simulate trials 8 seed 0 steps 60 levels rules_third
"""


def test_anticipation_lets_the_robot_with_a_private_goal_meet_its_team():
    # r1 alone knows the central goal g4 and knows the others do not. Without
    # anticipation it heads for g4 whenever it is cheapest and waits there alone; with
    # it, it predicts the others over the goals they know. Same seeds for both.
    mission = parse_mission(PRIVATE_GOAL, "private_goal.epi")
    off = dataclasses.replace(mission.parameters, anticipate=False)
    wins = {True: 0, False: 0}
    for seed in range(8):
        scenario, policies = mission.scenario(seed), mission.policies(seed)
        for flag, parameters in ((True, mission.parameters), (False, off)):
            trial = simulate(scenario, "rules-third", seed=seed, policies=policies,
                             parameters=parameters)  # fmt: skip
            wins[flag] += bool(trial.success)
    assert mission.parameters.anticipate
    assert wins[True] == 8 and wins[False] < 8
