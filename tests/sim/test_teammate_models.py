"""Teammate models in the closed loop (issue 19 §2): the stationary level, the parameter,
and a greedy teammate that the models let the team meet where the ablation cannot."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from epistemica.del_.errors import InvalidArgumentError
from epistemica.mission import load_mission
from epistemica.sim import Scenario, simulate
from epistemica.sim.levels import make_policy
from epistemica.sim.parameters import ActiveParameters

STRESS = Path(__file__).resolve().parents[2] / "specs" / "stress"


def test_a_stationary_robot_drives_to_one_goal_and_never_leaves_it():
    s = Scenario("allocation", [[0, 0, 0], [30, 0, 0]], [[5, 5], [25, 5], [15, 25]], ["range"] * 2)
    for seed in range(4):
        t = simulate(s, "stationary", seed=seed)
        goals = {int(g) for g in t.focal[:, 0, 0]}
        assert len(goals) == 1  # one goal, from the first step to the last
        final = t.trajectory[-1, 0, :2]
        assert np.hypot(*(final - s.goals[goals.pop()])) < 0.5  # arrived there


def test_the_models_are_a_parameter_on_at_order_two_and_above():
    assert ActiveParameters().teammate_models
    assert not make_policy(
        "third", ActiveParameters(teammate_models=False)
    ).parameters.teammate_models
    with pytest.raises(InvalidArgumentError, match="teammate_leak"):
        ActiveParameters(teammate_leak=2.0)
    with pytest.raises(InvalidArgumentError, match="teammate_sigma"):
        ActiveParameters(teammate_sigma=0.0)
    with pytest.raises(InvalidArgumentError, match="teammate_models must be true or false"):
        ActiveParameters(teammate_models="yes")


def _run(path: Path, seed: int, **changes):
    mission = load_mission(str(path))
    parameters = mission.parameters.replace(**changes) if changes else mission.parameters
    return simulate(
        mission.scenario(seed), "third", seed=seed, policies=mission.policies(seed),
        parameters=parameters,
    )  # fmt: skip


def test_with_a_silent_greedy_teammate_the_models_make_the_rendezvous():
    # Picked from the measured tuning trials: seed 1000 of the 3-robot rendezvous with one
    # greedy teammate (robot 2), no events, everyone in view. Without the models the two
    # others meet at the goal of least total distance and wait there for it; with them they
    # read it as greedy within a few steps and join it at its goal.
    path = STRESS / "rendezvous_adhoc_greedy_silent_3.epi"
    assert load_mission(str(path)).policies(1000) == {2: "zero"}
    on, off = _run(path, 1000), _run(path, 1000, teammate_models=False)
    assert on.success and not off.success
    greedy_goal = int(on.focal[-1, 2, 2])
    assert (on.focal[-1, [0, 1], [0, 1]] == greedy_goal).all()
