"""The ablation levels: expected free energy replaced by the prior's mode, and the
convention given every rule of the active levels (issue 19's fair baselines)."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.sim import Scenario, simulate
from epistemica.sim.policies.levels import LEVELS, make_policy


@pytest.mark.parametrize("level", ["first-priormode", "third-priormode", "convention+rules"])
def test_the_ablations_are_levels_with_their_names(level):
    assert level in LEVELS
    policy = make_policy(level)
    assert policy.name == level and not policy.parameters.free_energy


def test_convention_plus_rules_keeps_the_rules_and_drops_inference():
    p = make_policy("convention+rules").parameters
    assert p.search and p.pruning and p.common_view
    assert not (p.nested or p.anticipate or p.free_energy)
    assert make_policy("convention+rules").order == 2


@pytest.mark.parametrize("level", ["third-priormode", "convention+rules"])
@pytest.mark.parametrize("mission", ["rendezvous", "allocation"])
def test_a_prior_mode_robot_drives_straight_at_its_focal_goal(level, mission):
    # Each step the robot turns to face its own goal in the configuration it recorded as
    # focal and moves at full speed, never past it: the distance falls by exactly
    # max_speed * dt (or to 0). The expected-free-energy levels do not (their grid moves
    # a robot up to 0.18 m off it, in every step of the same allocation trials).
    for seed in range(4):
        scenario = Scenario.paper(mission, 3, seed=seed)
        trial = simulate(scenario, level, seed=seed)
        for t in range(trial.steps - 1):
            for i in range(3):
                goal = trial.focal[t, i, i]
                if goal < 0:
                    continue
                before = np.hypot(*(trial.trajectory[t, i, :2] - scenario.goals[goal]))
                after = np.hypot(*(trial.trajectory[t + 1, i, :2] - scenario.goals[goal]))
                step = scenario.max_speed[i] * scenario.dt
                assert after == pytest.approx(max(before - step, 0.0), abs=1e-9)
