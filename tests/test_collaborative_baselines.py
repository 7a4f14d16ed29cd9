"""The collaborative baselines ``recruit`` and ``convention+rules`` against ``third``, each
on a small scene worked by hand (sim/policies/collaborative_levels.py): both recruit as ``third``
does, neither knows which teammates know of a task."""

import numpy as np
import pytest

from epistemica.sim import simulate
from epistemica.sim.engine.joint import JointView
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.policies.collaborative_levels import (
    FETCHING,
    first_order,
)
from epistemica.sim.policies.levels import level_names, make_level


def _scene(starts, tasks, needs, finders):
    """Robots at ``starts``, everyone seeing everyone now (step 50); task ``t`` found by
    the robots ``finders[t]`` together (each knows the others know it)."""
    s = CollaborativeScenario(starts, tasks, needs, workspace=30.0, sensing_range=7.0)
    n, m = len(starts), len(tasks)
    k = TeamKnowledge(s.robot_names, s.task_names, np.zeros((n, m), dtype=bool))
    for t, mask in enumerate(finders):
        k.discover(t, np.array(mask))
    poses = np.asarray(s.starts, dtype=float)
    aware = np.array(
        [[k.knows_goals((i,) if i == j else (i, j)) for j in range(n)] for i in range(n)]
    )
    view = JointView(50, poses, np.repeat(poses[None, :, :2], n, axis=0), np.full((n, n), 50), k,
                aware, np.where(aware, 0, -1), np.full((n, m), 50))  # fmt: skip
    return s, view


def _decide(level, s, view):
    policy = make_level("collaborative", level)
    policy.start(s)
    targets, steer_to = policy.plan(view)
    return targets[0].tolist(), int(steer_to[0])


def test_the_baselines_are_levels_of_the_registry():
    assert {"recruit", "convention+rules"} <= set(level_names("collaborative"))


def test_first_order_knowledge_forgets_what_teammates_know():
    _, view = _scene([[20, 15, 0], [26.5, 15, 0]], [[3, 15]], (2,), [[True, True]])
    assert view.aware[0, 1, 0]
    seen = first_order(view)
    assert seen.aware[:, :, 0].tolist() == [[True, False], [False, True]]
    assert seen.since[0, 1, 0] == -1 and seen.since[0, 0, 0] == 0


def test_a_teammate_known_to_know_is_fetched_by_the_baselines_but_not_by_third():
    # r1 (20, 15) and r2 (26.5, 15) found t1 (3, 15), which needs 2, together. `third`
    # knows r2 knows: both are sent, r1 heads for t1. The baselines do not know it: r1
    # fetches r2, the teammate seen lately nearest t1, and goes towards it (6.5 m off,
    # beyond the 7 - 2 = 5 m from which it would turn back).
    s, view = _scene([[20, 15, 0], [26.5, 15, 0]], [[3, 15]], (2,), [[True, True]])
    assert _decide("rules", s, view) == ([3.0, 15.0], 0)
    assert _decide("recruit", s, view) == ([26.5, 15.0], FETCHING)
    assert _decide("convention+rules", s, view) == ([26.5, 15.0], FETCHING)
    assert _decide("rules-first", s, view) == ([3.0, 15.0], 0)  # no recruiting at all


@pytest.mark.parametrize(
    ("r2", "steer", "goes_to"),
    [([3.5, 15.0], 0, [3.0, 15.0]), ([26.5, 15.0], FETCHING, [26.5, 15.0])],
)
def test_recruit_stops_fetching_once_enough_teammates_stand_at_the_task(r2, steer, goes_to):
    # r1 alone knows t1 (3, 15), needs 2. r2 does not know it. Standing 0.5 m from t1
    # (within 2 x 1.5 m) r2 is seen at it: r1 goes there. 6.5 m east of r1, r2 is fetched.
    s, view = _scene([[20, 15, 0], [*r2, 0]], [[3, 15]], (2,), [[True, False]])
    assert _decide("recruit", s, view) == (goes_to, steer)


def test_convention_rules_keeps_the_rules_but_fetches_a_teammate_that_knows():
    # r1 (6, 15) and r2 (12, 15) found t1 (5, 15), which needs 3, together; r3 (25, 15)
    # does not know. `third`: r2 fetches r3 and r1, the knower nearest t1, goes for r3 too
    # (`fetch_together`: nobody else may see it wait). `convention+rules` does not know r2
    # knows: r1 fetches the teammate nearest t1, r2 (7 m from t1, beyond 0.8 x 7 m: not
    # waited for), 6 m off. `recruit` sees nobody at t1 and does the same.
    s, view = _scene([[6, 15, 0], [12, 15, 0], [25, 15, 0]], [[5, 15]], (3,),
                     [[True, True, False]])  # fmt: skip
    assert _decide("rules", s, view) == ([25.0, 15.0], FETCHING)
    assert _decide("convention+rules", s, view) == ([12.0, 15.0], FETCHING)
    assert _decide("recruit", s, view) == ([12.0, 15.0], FETCHING)


@pytest.mark.parametrize("level", ["recruit", "convention+rules"])
def test_a_baseline_completes_a_two_robot_task(level):
    # two robots 10 m apart, a task between them needing both, 7 m sight: done
    s = CollaborativeScenario([[10, 10, 0], [20, 10, 0]], [[15, 12]], (2,), workspace=30.0,
                              sensing_range=7.0, max_steps=200)  # fmt: skip
    trial = simulate(s, level, seed=0)
    assert trial.success
