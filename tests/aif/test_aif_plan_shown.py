"""The value of being seen (``Planner(shown=...)``, ``plan(watching=...)``, ``plan_shown``):
each option scored with the watching teammates predicted from what they would see."""

import numpy as np
import pytest

from epistemica import InvalidArgumentError
from epistemica.aif.planning import Planner
from epistemica.del_.errors import EpistemicaError
from epistemica.sim.policies.parameters import ActiveParameters

GOALS = np.array([[0.0, 0.0], [10.0, 0.0]])
SWAP = [[0, 1], [1, 0]]  # allocation of two robots to two goals
AT = np.array([[3.0, 0.0], [5.0, 4.0]])  # robot 0 nearer goal 0; robot 1 midway
READ = np.array([[0.0, 0.0], [0.0, -2.0]])  # robot 1 seen leaning towards goal 0


def _step_evidence(here, goal: int, shown: float, sigma: float) -> np.ndarray:
    """``(m,)`` nats a watcher reads of ``shown`` unit steps from ``here`` towards ``goal``,
    under each goal: ``-|step - step'|^2 / 2 sigma^2`` per step (worked by hand)."""
    unit = (GOALS - here) / np.hypot(*(GOALS - here).T)[:, None]
    return -shown * ((unit[goal] - unit) ** 2).sum(axis=1) / (2 * sigma**2)


def test_each_option_is_scored_with_the_watcher_predicted_from_the_sight():
    # Order 2, unit speeds, dt 1, tau = 10 s (temperature 1, goals 10 m apart), sigma 0.5 m,
    # success weight 3 (the value this example was worked at).
    # For robot 0's goal g the allocation forms iff robot 1 takes the other goal, so
    # G(g) = T / tau - 3 ln pi_1(1 - g), T the later arrival; pi_1 is robot 1's prediction
    # when robot 0's row carries the evidence of two steps towards g.
    weighed = dict(order=2, temperature=1.0, success_weight=3.0)
    planner = Planner(GOALS, SWAP, [1.0, 1.0], shown=2.0, **weighed)
    result = planner.plan(0, AT, evidence=READ, watching=[False, True])
    plain = Planner(GOALS, SWAP, [1.0, 1.0], **weighed)
    times = np.hypot(*(GOALS[None] - AT[:, None]).transpose(2, 0, 1))  # (robot, goal) s
    for g in (0, 1):
        seen = READ.copy()
        seen[0] += _step_evidence(AT[0], g, 2.0, 0.5)
        pi = plain.plan(0, AT, evidence=seen).predictions[1]
        finish = max(times[0, g], times[1, 1 - g])
        assert result.G[g] == pytest.approx(finish / 10.0 - 3.0 * np.log(pi[1 - g]))
    # Unwatched, robot 1's lean makes goal 0 risky and robot 0 goes to the far goal 1;
    # seen heading for goal 0, robot 1 is predicted to yield, and robot 0 takes goal 0.
    assert plain.plan(0, AT, evidence=READ).goal == 1
    assert result.goal == 0


def test_nobody_watching_or_order_one_or_zero_steps_change_nothing():
    args = dict(evidence=READ)
    reference = Planner(GOALS, SWAP, [1.0, 1.0], order=2).plan(0, AT, **args).G
    shown = Planner(GOALS, SWAP, [1.0, 1.0], order=2, shown=3.0)
    np.testing.assert_array_equal(shown.plan(0, AT, watching=[False, False], **args).G, reference)
    np.testing.assert_array_equal(shown.plan(0, AT, watching=[True, False], **args).G, reference)
    off = Planner(GOALS, SWAP, [1.0, 1.0], order=2, shown=0.0)
    np.testing.assert_array_equal(off.plan(0, AT, watching=[False, True], **args).G, reference)
    first = Planner(GOALS, SWAP, [1.0, 1.0], order=1, shown=3.0)
    np.testing.assert_array_equal(
        first.plan(0, AT, watching=[False, True], **args).G,
        Planner(GOALS, SWAP, [1.0, 1.0], order=1).plan(0, AT, **args).G,
    )


def test_shown_is_checked():
    with pytest.raises(InvalidArgumentError, match="shown"):
        Planner(GOALS, SWAP, [1.0, 1.0], shown=-1.0)
    with pytest.raises(EpistemicaError, match="plan_shown"):
        ActiveParameters(plan_shown=-0.5)
    with pytest.raises(EpistemicaError, match="plan_shown"):
        ActiveParameters(plan_shown=True)
