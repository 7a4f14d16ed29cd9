"""The environment's bounded spaces, global state, epistemic observations, registered ids
and its answers to bad arguments."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")  # in the test extra: skipped only without it
pytest.importorskip("pettingzoo")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from epistemica.del_.errors import InvalidArgumentError  # noqa: E402
from epistemica.mission import load_mission  # noqa: E402
from epistemica.sim import Scenario, simulate  # noqa: E402
from epistemica.sim.engine.env import MissionEnv, RobotEnv  # noqa: E402
from epistemica.sim.engine.env_registry import PaperFamily  # noqa: E402
from epistemica.sim.engine.vector_env import VectorMissionEnv  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
PRIVATE = ROOT / "specs" / "nested" / "private_goal_3.epi"


@pytest.mark.parametrize("family", ["Rendezvous", "Allocation", "Multitask"])
def test_registered_ids_make_a_robot_env_that_passes_check_env_without_a_warning(family):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning fails
        env = gymnasium.make(f"epistemica/{family}-v0")
        check_env(env.unwrapped, skip_render_check=True)
    env.reset(seed=3)
    mission = {"Rendezvous": "rendezvous", "Allocation": "allocation", "Multitask": "multitask"}
    goals = 5 if family == "Multitask" else 3
    expected = Scenario.paper(mission[family], 3, goals, seed=3)
    assert np.array_equal(env.unwrapped.multi.scenario.starts, expected.starts)
    assert np.array_equal(env.unwrapped.multi.scenario.goals, expected.goals)


def test_a_mission_file_with_epistemic_observations_passes_check_env_too():
    env = RobotEnv(load_mission(PRIVATE), teammates="zero", epistemic=True, normalized=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env, skip_render_check=True)


def test_normalised_actions_map_onto_the_robots_limits():
    s = Scenario.paper("rendezvous", 2, 2, seed=4, max_steps=6)
    physical, normal = MissionEnv(s), MissionEnv(s, normalized=True)
    physical.reset(seed=4)
    normal.reset(seed=4)
    rng = np.random.default_rng(0)
    for _ in range(6):
        a = rng.uniform(-1, 1, size=(2, 2))
        speed = (a[:, 0] + 1) / 2 * s.max_speed
        turn = a[:, 1] * s.max_turn
        physical.step({r: np.array([speed[i], turn[i]]) for i, r in enumerate(["r1", "r2"])})
        normal.step({r: a[i] for i, r in enumerate(["r1", "r2"])})
    assert np.allclose(physical.trial().trajectory, normal.trial().trajectory)


def test_state_is_the_true_poses_goals_open_goals_and_time():
    mission = load_mission(ROOT / "specs" / "events" / "door_closes.epi")
    env = MissionEnv(mission)
    env.reset(seed=2)
    for _ in range(5):
        env.step(env.level_actions("convention"))
    state, s = env.state(), env.scenario
    assert env.state_space.contains(state)
    n, m = s.n_robots, s.n_goals
    poses = env.trial().trajectory[-1]
    assert np.allclose(state[: 3 * n].reshape(n, 3)[:, :2], poses[:, :2], atol=1e-4)
    heading = state[: 3 * n].reshape(n, 3)[:, 2]
    assert np.allclose(np.cos(heading), np.cos(poses[:, 2]), atol=1e-4)
    assert np.allclose(state[3 * n : 3 * n + 2 * m], s.goals.ravel())
    assert state[-1] == pytest.approx(5 / s.max_steps)


def test_epistemic_observations_are_the_trials_knowledge():
    mission = load_mission(PRIVATE)
    env = MissionEnv(mission, epistemic=True)
    observations, _ = env.reset(seed=4)
    seen = [observations]
    while env.agents:
        observations, *_ = env.step(env.level_actions("rules-third"))
        if env.agents:
            seen.append(observations)
    trial = simulate(mission.scenario(4), "rules-third", seed=4, parameters=mission.parameters)
    assert trial.steps == len(seen)
    for step, views in enumerate(seen):
        for i, robot in enumerate(["r1", "r2", "r3"]):
            assert np.array_equal(views[robot]["teammates_know"], trial.known_goals[step, i])
    # r1 alone knows of g4 and takes the others not to know of it.
    assert seen[0]["r1"]["teammates_know"][:, 3].tolist() == [1, 0, 0]


@pytest.mark.parametrize("seed", ["abc", math.nan, math.inf, 1.5, True, -1])
def test_a_bad_seed_is_refused_with_what_to_do(seed):
    env = MissionEnv(Scenario.paper("rendezvous", 2, 2, seed=0))
    with pytest.raises(InvalidArgumentError, match=r"seed.*whole number >= 0") as info:
        env.reset(seed=seed)
    assert "reset(seed=0)" in info.value.hint
    with pytest.raises(InvalidArgumentError, match="whole number >= 0"):
        RobotEnv(Scenario.paper("rendezvous", 2, 2, seed=0)).reset(seed=seed)
    with pytest.raises(InvalidArgumentError, match="whole number >= 0"):
        MissionEnv(Scenario.paper("rendezvous", 2, 2, seed=0), seed=seed)


@pytest.mark.parametrize("shaping", ["x", math.nan, math.inf, None, True])
def test_a_bad_shaping_weight_is_refused(shaping):
    with pytest.raises(InvalidArgumentError, match="shaping must be a finite number"):
        MissionEnv(Scenario.paper("rendezvous", 2, 2, seed=0), shaping=shaping)


def test_step_without_a_mapping_or_for_an_unknown_agent_is_refused():
    env = MissionEnv(Scenario.paper("rendezvous", 3, 2, seed=0), teammates={"r3": "zero"})
    env.reset(seed=0)
    with pytest.raises(InvalidArgumentError, match="mapping from agent to action"):
        env.step(None)
    actions = {"r1": np.zeros(2), "r2": np.zeros(2)}
    with pytest.raises(InvalidArgumentError, match=r"unknown agent\(s\) \['r9'\]") as info:
        env.step({**actions, "r9": np.zeros(2)})
    assert "['r1', 'r2']" in info.value.hint
    with pytest.raises(InvalidArgumentError, match=r"unknown agent\(s\) \['r3'\]"):
        env.step({**actions, "r3": np.zeros(2)})  # a scripted teammate is no agent
    env.step(actions)  # and the trial goes on
    assert env.step_count == 1


def test_the_other_bad_arguments_are_refused_with_what_to_pass():
    s = Scenario.paper("rendezvous", 2, 2, seed=0)
    with pytest.raises(InvalidArgumentError, match="teammates must map robots to levels"):
        MissionEnv(s, teammates=["r1"])
    with pytest.raises(InvalidArgumentError, match="a level's name or a Policy"):
        RobotEnv(s, teammates=["rules-third"])
    with pytest.raises(InvalidArgumentError, match=r"unknown keyword.*colour") as info:
        RobotEnv(s, colour="red")
    assert "shaping" in info.value.hint
    with pytest.raises(InvalidArgumentError, match="no robot 'r7'"):
        RobotEnv(s, robot="r7")
    assert RobotEnv(s, robot=np.int64(1)).agent == "r2"  # numpy's integers are indices too
    env = MissionEnv(s)
    with pytest.raises(InvalidArgumentError, match=r"options=\.\.\.\) must be a dict"):
        env.reset(seed=0, options=5)
    env.reset(seed=0, options={})
    env.reset(seed=np.int64(2))
    assert env.seed_ == 2


def test_the_vectorised_env_refuses_bad_arguments_too():
    family = PaperFamily("rendezvous", 2, 2)
    for count in (0, True, "4", 2.5):
        with pytest.raises(InvalidArgumentError, match="num_envs must be a whole number >= 1"):
            VectorMissionEnv(family, num_envs=count)
    assert VectorMissionEnv(family, num_envs=np.int64(2)).num_envs == 2
    env = VectorMissionEnv(family, num_envs=2)
    with pytest.raises(InvalidArgumentError, match="call reset"):
        env.step(np.zeros((2, 2, 2)))
    with pytest.raises(InvalidArgumentError, match="shaping must be a finite number"):
        VectorMissionEnv(family, num_envs=2, shaping=math.nan)
    env.reset(seed=0)
    for bad in (None, "abc", np.zeros((3, 2, 2)), np.full((2, 2, 2), np.nan)):
        with pytest.raises(InvalidArgumentError, match=r"finite \(2, 2, 2\) array"):
            env.step(bad)
