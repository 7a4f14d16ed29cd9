"""The environment over collaborative missions: it steps the simulator's joint run, so a
level's actions through it give ``simulate``'s trial; the spaces pass PettingZoo's and
Gymnasium's checks; observations are what each robot perceives and knows; the reward adds
up to the tasks done plus the shaping."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("gymnasium")  # in the test extra: skipped only without it
pytest.importorskip("pettingzoo")

from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test
from test_env import _assert_same_trial as assert_same_trial
from test_env import _through_env

from epistemica.del_.errors import InvalidArgumentError
from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.env import MissionEnv, RobotEnv
from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.vector_env import VectorMissionEnv
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.study.palette import ROBOT_COLOURS

FOLDER = Path(__file__).resolve().parents[2] / "specs" / "collaborative"
SHIPPED = sorted(FOLDER.glob("*.epi"))


def _assert_same_trial(a, b):
    assert_same_trial(a, b)
    assert np.array_equal(a.steer_to, b.steer_to) and np.array_equal(a.knows, b.knows)
    assert np.array_equal(a.tasks_done, b.tasks_done)
    assert a.completion_step == b.completion_step


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
@pytest.mark.parametrize("level", ["convention", "rules"])
def test_a_levels_actions_through_the_env_are_simulates_trial(path, level):
    mission = load_mission(path)
    env = MissionEnv(mission, parameters=mission.parameters)
    trial = _through_env(env, 1, level)
    expected = simulate(mission.scenario(1), level, 1, parameters=mission.parameters)
    _assert_same_trial(trial, expected)


def test_scripted_teammates_play_their_level_beside_the_agents():
    mission = load_mission(FOLDER / "tasks_5.epi")
    env = MissionEnv(mission, {"r1": "rules", "r4": "rules"}, parameters=mission.parameters)
    assert env.possible_agents == ["r2", "r3", "r5"]
    trial = _through_env(env, 3, "convention")
    policies = {0: "rules", 3: "rules"}
    expected = simulate(
        mission.scenario(3), "convention", 3, parameters=mission.parameters, policies=policies
    )
    _assert_same_trial(trial, expected)
    assert trial.policies == ("rules", "env", "env", "rules", "env")


def test_an_agent_that_plays_its_own_actions_declares_no_task():
    mission = load_mission(FOLDER / "tasks_3.epi")
    env = MissionEnv(mission, {"r1": "rules"})
    env.reset(seed=0)
    for _ in range(5):
        advised = env.level_actions("rules")
        env.step({a: np.clip(advised[a] * 0.5, -1, 1) for a in env.agents})  # not the level's
    assert (env.trial().steer_to[:, 1:] == -1).all()  # exploring, as far as anyone can tell


def test_pettingzoo_and_gymnasium_checks_pass_without_a_warning():
    mission = load_mission(FOLDER / "tasks_3.epi")
    parallel_api_test(MissionEnv(mission, epistemic=True), num_cycles=300)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(
            RobotEnv(mission, teammates="convention", normalized=True), skip_render_check=True
        )


def test_observations_are_the_robots_perception_and_knowledge():
    s = CollaborativeScenario(
        [[1.0, 1.0, 0.0], [30.0, 30.0, 0.0]], [[3.0, 1.0], [30.0, 28.0]], (1, 2),
        workspace=40.0, sensing_range=5.0,
    )  # fmt: skip
    env = MissionEnv(s, epistemic=True)
    views, _ = env.reset(seed=0)
    # r1 sees t1 (2 m away) but not r2 nor t2; r2 sees t2, not r1
    assert views["r1"]["known_tasks"].tolist() == [1, 0]
    assert views["r2"]["known_tasks"].tolist() == [0, 1]
    assert views["r1"]["tasks"][0].tolist() == [3.0, 1.0] and views["r1"]["tasks"][1].tolist() == [
        0,
        0,
    ]
    assert views["r1"]["needs"].tolist() == [1, 0] and views["r2"]["needs"].tolist() == [0, 2]
    assert views["r1"]["seen"].tolist() == [1, 0]
    assert views["r1"]["teammates_know"].tolist() == [[1, 0], [0, 0]]  # it knows nothing of r2
    assert views["r1"]["done"].tolist() == [0, 0]
    # r1 drives onto t1 (needs one robot): done, and r1 knows it
    for _ in range(3):
        views, *_ = env.step({"r1": np.array([1.0, 0.0]), "r2": np.zeros(2)})
    assert env.run.done[0] >= 0 and views["r1"]["done"].tolist() == [1, 0]
    assert views["r2"]["done"].tolist() == [0, 0]  # r2 saw nothing of it
    for agent in env.agents:
        assert env.observation_space(agent).contains(views[agent])
    assert env.state_space.contains(env.state())


def test_rewards_add_up_to_the_tasks_done_plus_the_shaping():
    mission = load_mission(FOLDER / "tasks_3.epi")
    env = MissionEnv(mission, shaping=0.5)
    env.reset(seed=2)
    s = env.scenario
    d = distances(s.starts, s.tasks).min(axis=1)
    first = -float(np.maximum(d - s.completion_radius, 0).sum()) / (s.n_robots * s.workspace)
    total = 0.0
    while env.agents:
        _, rewards, *_ = env.step(env.level_actions("convention"))
        total += rewards["r1"]
    done = np.count_nonzero(env.run.done >= 0) / s.n_tasks
    undone = env.run.done < 0
    last = 0.0
    if undone.any():
        d = distances(env.run.poses, s.tasks[undone]).min(axis=1)
        last = -float(np.maximum(d - s.completion_radius, 0).sum()) / (s.n_robots * s.workspace)
    assert total == pytest.approx(done + 0.5 * (last - first))


def test_teammates_that_share_and_that_do_not_are_refused_together():
    mission = load_mission(FOLDER / "tasks_3.epi")
    env = MissionEnv(mission, {"r1": "oracle", "r2": "rules"})
    with pytest.raises(InvalidArgumentError, match="share what they see"):
        env.reset(seed=0)


def test_render_draws_the_collaborative_trial_so_far():
    mission = load_mission(FOLDER / "tasks_3.epi")
    env = MissionEnv(mission, render_mode="rgb_array")
    env.reset(seed=1)
    for _ in range(5):
        env.step(env.level_actions("rules"))
    image = env.render()
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
    # the robots' colours are on it (their trails and ends), as plot_trial draws them
    for colour in ROBOT_COLOURS[:3]:
        rgb = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)])
        assert (np.abs(image.astype(int) - rgb).sum(axis=2) < 40).sum() > 20, colour


def test_the_vectorised_env_refuses_a_collaborative_mission_with_a_pointer():
    with pytest.raises(InvalidArgumentError, match="collaborative mission") as info:
        VectorMissionEnv(load_mission(FOLDER / "tasks_3.epi"), num_envs=2)
    assert "MissionEnv" in info.value.hint
