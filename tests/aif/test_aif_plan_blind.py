"""Teammates never seen (``Planner.plan(..., blind=...)``, ``plan_blind``): hand-worked
predictions without the robot's evidence."""

import numpy as np
import pytest

from epistemica import InvalidArgumentError
from epistemica.aif.planning import Planner
from epistemica.del_.errors import EpistemicaError
from epistemica.sim.policies.parameters import ActiveParameters

GOALS = [[0.0, 0.0], [10.0, 0.0]]


def test_a_placeholder_is_no_evidence_of_a_never_seen_teammate():
    # Order 1, two robots meeting at goal 0 or 1; tau = 10 s, repair = 10 s (as in
    # test_aif_planning). Robot 1 was never seen: its placeholder (10, 0) sits on goal 1,
    # but it is predicted from the uniform prior alone, 1/2 each.
    planner = Planner(GOALS, [[0, 0], [1, 1]], [1.0, 1.0], order=1, temperature=1.0,
                      repair=1.0, success_weight=0.0)  # fmt: skip
    positions = [[4.0, 0.0], [10.0, 0.0]]
    result = planner.plan(0, positions, blind=[False, True])
    np.testing.assert_allclose(result.predictions[1], [0.5, 0.5])
    # The own costs still time robot 1 from its placeholder: finish max(4, 10), max(6, 0).
    expected = 0.5 * np.array([10.0, 6.0]) + 0.5 * (np.array([4.0, 6.0]) + 10.0)
    np.testing.assert_allclose(result.G, expected / 10.0)
    seen = planner.plan(0, positions, blind=[False, False])
    np.testing.assert_allclose(seen.G, planner.plan(0, positions).G)
    assert seen.predictions[1, 1] > 0.5  # seen there, it is read as heading for goal 1


def test_a_never_seen_predictor_does_not_inherit_the_robots_evidence():
    # Three robots meet at goal 0 or 1, order 2. Robot 0 saw robot 2 head for goal 1
    # (50 nats); robot 1 it never saw. Robot 0 predicts robot 1 at order 1, and robot 1's
    # predictions of robots 0 and 2 at order 0 are the prior's marginals (1/2 each) with
    # no evidence: robot 1 is not credited with robot 0's sightings.
    planner = Planner(GOALS, [[0, 0, 0], [1, 1, 1]], [1.0] * 3, order=2, temperature=1.0,
                      repair=1.0, success_weight=0.0)  # fmt: skip
    positions = np.array([[4.0, 0.0], [5.0, 0.0], [9.0, 0.0]])
    moves = np.array([[0.0, 0.0], [0.0, 0.0], [-50.0, 0.0]])
    blind = planner.plan(0, positions, evidence=moves, blind=[False, True, False])
    # Each meeting forms with probability 1/4; it ends at max(4, 5, 9) = 9 s at goal 0
    # and max(6, 5, 1) = 6 s at goal 1; a mismatch costs robot 1's 5 s trip + 10 s.
    G = 0.25 * np.array([9.0, 6.0]) + 0.75 * (np.array([5.0, 5.0]) + 10.0)
    q = np.exp(-G / 10.0)
    np.testing.assert_allclose(blind.predictions[1], q / q.sum())
    # Without the mark, robot 1 is predicted to follow robot 2 to goal 1 (the inheritance).
    inherits = planner.plan(0, positions, evidence=moves)
    assert inherits.predictions[1, 1] > blind.predictions[1, 1] + 0.05


def test_blind_is_checked():
    planner = Planner(GOALS, [[0, 0], [1, 1]], [1.0, 1.0], order=1)
    with pytest.raises(InvalidArgumentError, match="blind"):
        planner.plan(0, [[4.0, 0.0], [10.0, 0.0]], blind=[True])
    with pytest.raises(EpistemicaError):
        ActiveParameters(plan_blind=1)
