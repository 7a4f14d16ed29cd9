"""The PettingZoo / Gymnasium environment (sim/engine/env.py)."""

from __future__ import annotations

import runpy
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")  # in the test extra: skipped only without it
pettingzoo = pytest.importorskip("pettingzoo")

from gymnasium.utils.env_checker import check_env  # noqa: E402
from pettingzoo.test import parallel_api_test  # noqa: E402

from epistemica.del_.errors import InvalidArgumentError, SourceError  # noqa: E402
from epistemica.mission import load_mission  # noqa: E402
from epistemica.sim import Scenario, simulate  # noqa: E402
from epistemica.sim.engine.env import MissionEnv, RobotEnv  # noqa: E402
from epistemica.sim.engine.missions import distances  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def _shipped(stress: bool) -> list[Path]:
    """Every mission file under specs/ the simulator runs (spec files are not missions);
    the stress suite's variants apart."""
    out = []
    for path in sorted((ROOT / "specs").rglob("*.epi")):
        if ("stress" in path.parts) != stress:
            continue
        try:
            mission = load_mission(path)
        except SourceError:
            continue
        if not mission.kind.joint:  # collaborative: tests/sim/test_env_joint.py
            out.append(path)
    return out


SHIPPED = _shipped(stress=False)
STRESS = _shipped(stress=True)


def _ids(paths):
    return [str(p.relative_to(ROOT / "specs")) for p in paths]


def test_every_kind_of_shipped_mission_is_covered():
    kinds = {load_mission(p).kind.name for p in SHIPPED}
    assert kinds == {"rendezvous", "allocation", "capacity", "multitask"}
    assert len(SHIPPED) >= 15 and len(STRESS) == 110


@pytest.mark.parametrize("path", SHIPPED + STRESS, ids=_ids(SHIPPED + STRESS))
def test_pettingzoo_and_gymnasium_api_checks_pass(path):
    mission = load_mission(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # advice only: unbounded positions, unnormalised actions
        parallel_api_test(MissionEnv(mission), num_cycles=1000)
        check_env(RobotEnv(mission, teammates="zero"), skip_render_check=True)


def _through_env(env: MissionEnv, seed: int, level: str):
    env.reset(seed=seed)
    while env.agents:
        env.step(env.level_actions(level))
    return env.trial()


def _assert_same_trial(a, b):
    assert np.array_equal(a.trajectory, b.trajectory)
    assert np.array_equal(a.estimates, b.estimates)
    assert a.events == b.events
    assert (a.success, a.steps) == (b.success, b.steps)


@pytest.mark.parametrize("path", SHIPPED, ids=_ids(SHIPPED))
def test_the_env_with_a_levels_actions_is_simulates_trial(path):
    mission = load_mission(path)
    seed = 1
    env_trial = _through_env(MissionEnv(mission), seed, "convention")
    _assert_same_trial(env_trial, simulate(mission.scenario(seed), "convention", seed=seed))


@pytest.mark.parametrize("name", ["rendezvous.epi", "events/door_closes.epi", "multi_task.epi"])
def test_the_env_reproduces_the_active_inference_level_too(name):
    mission = load_mission(ROOT / "specs" / name)
    seed = 2
    _assert_same_trial(
        _through_env(MissionEnv(mission), seed, "rules-third"),
        simulate(mission.scenario(seed), "rules-third", seed=seed),
    )


def test_scripted_teammates_are_simulates_policies():
    s = Scenario.paper("allocation", 3, seed=4, sensing_range=12.0)
    env = MissionEnv(s, teammates={"r1": "zero"})
    assert env.possible_agents == ["r2", "r3"]
    trial = _through_env(env, 4, "rules-third")
    expected = simulate(s, "rules-third", seed=4, policies={0: "zero"})
    _assert_same_trial(trial, expected)
    assert trial.policies == ("zero", "env", "env")
    assert np.array_equal(trial.focal[:, 0], expected.focal[:, 0])  # the teammate's record


def test_contacts_and_obstacles_run_through_the_env_too():
    s = Scenario.paper("rendezvous", 3, 2, seed=0, robot_radius=0.5)
    _assert_same_trial(_through_env(MissionEnv(s), 0, "convention"), simulate(s, "convention", 0))


def test_seeded_resets_repeat_and_seeds_differ():
    env = MissionEnv(load_mission(ROOT / "specs" / "rendezvous.epi"))
    first, _ = env.reset(seed=7)
    again, _ = env.reset(seed=7)
    other, _ = env.reset(seed=8)
    for key in first["r1"]:
        assert np.array_equal(first["r1"][key], again["r1"][key])
    assert not np.array_equal(first["r1"]["goals"], other["r1"]["goals"])  # a new layout
    env.reset()
    assert env.seed_ == 9  # without a seed: the next one


def test_observations_are_the_robots_perception():
    s = Scenario.paper("allocation", 3, seed=3, sensing_range=10.0, discovery_range=6.0)
    s = s.replace(known_goals=np.eye(3, dtype=bool))
    env = MissionEnv(s)
    views, _ = env.reset(seed=3)
    team = env.observations
    for i, agent in enumerate(env.agents):
        view = views[agent]
        assert np.allclose(view["pose"], s.starts[i], atol=1e-6)
        assert np.allclose(view["teammates"], team.poses[i, :, :2], atol=1e-5)
        assert view["seen"].tolist() == team.seen[i].astype(int).tolist()
        known = team.known_goals[i]
        assert view["known_goals"].tolist() == known.astype(int).tolist()
        assert np.allclose(view["goals"][known], s.goals[known], atol=1e-5)
        assert not view["goals"][~known].any()
        within = distances(s.starts[:, :2], s.starts[:, :2])[i] <= 10.0
        assert view["seen"].astype(bool).tolist() == within.tolist()


def test_events_seen_are_the_trials_events():
    mission = load_mission(ROOT / "specs" / "events" / "door_closes.epi")
    env = MissionEnv(mission)
    views, _ = env.reset(seed=0)
    rules = [r.name for r in env.scenario.events]
    seen = [views]
    while env.agents:
        views, *_ = env.step(env.level_actions("convention"))
        seen.append(views)
    trial = env.trial()
    assert trial.events, "the door must close in this trial for the test to say anything"
    for step, step_views in enumerate(seen[: trial.steps]):
        for i, agent in enumerate(env.possible_agents):
            expected = np.zeros(len(rules), dtype=int)
            for event in trial.events:
                if event[0] == step and i in event[-1]:
                    expected[rules.index(event[1])] = 1
            assert step_views[agent]["events"].tolist() == expected.tolist(), (step, agent)


def _potential(s, poses):
    d = distances(poses, s.goals).min(axis=1)
    return -np.mean(np.maximum(d - s.success_radius, 0.0)) / s.workspace


def test_rewards_add_up_to_progress_plus_shaping():
    s = Scenario.paper("rendezvous", 3, 3, seed=0)
    for shaping in (0.0, 0.5):
        env = MissionEnv(s, shaping=shaping)
        env.reset(seed=0)
        total = 0.0
        while env.agents:
            _, rewards, terminations, truncations, _ = env.step(env.level_actions("convention"))
            assert len(set(rewards.values())) == 1  # one team reward
            total += rewards["r1"]
        trial = env.trial()
        assert trial.success and all(terminations.values()) and not any(truncations.values())
        ends = _potential(s, trial.trajectory[-1]) - _potential(s, trial.trajectory[0])
        assert total == pytest.approx(1.0 + shaping * ends)
        assert env.returns["r2"] == pytest.approx(total)


def test_standing_still_is_truncated_with_no_progress():
    s = Scenario.paper("allocation", 2, seed=1).replace(max_steps=5)
    env = MissionEnv(s, shaping=0.0)
    env.reset(seed=1)
    steps = 0
    while env.agents:
        _, rewards, terminations, truncations, _ = env.step({a: np.zeros(2) for a in env.agents})
        steps += 1
        assert rewards == {"r1": 0.0, "r2": 0.0}
    assert steps == 5 and all(truncations.values()) and not any(terminations.values())


def test_the_final_observation_has_the_final_pose():
    s = Scenario.paper("rendezvous", 2, 2, seed=0)
    env = MissionEnv(s)
    env.reset(seed=0)
    while env.agents:
        views, *_ = env.step(env.level_actions("convention"))
    assert np.allclose(views["r1"]["pose"], env.trial().trajectory[-1, 0], atol=1e-5)


def test_multitask_reward_counts_tasks():
    mission = load_mission(ROOT / "specs" / "multi_task.epi")
    env = MissionEnv(mission, shaping=0.0)
    env.reset(seed=0)
    total = 0.0
    while env.agents:
        _, rewards, *_ = env.step(env.level_actions("convention"))
        total += rewards["r1"]
    trial = env.trial()
    assert total == pytest.approx(np.count_nonzero(trial.tasks_done >= 0) / len(trial.tasks_done))


def test_the_gymnasium_view_drives_one_robot():
    s = Scenario.paper("rendezvous", 3, 3, seed=2)
    env = RobotEnv(s, robot="r2", teammates="convention")
    observation, _ = env.reset(seed=2)
    assert env.observation_space.contains(observation)
    done = False
    while not done:  # the learner copies the convention: the trial is simulate's
        action = env.multi.level_actions("convention")["r2"]
        observation, _, terminated, truncated, _ = env.step(action)
        assert env.observation_space.contains(observation)
        done = terminated or truncated
    _assert_same_trial(env.trial(), simulate(s, "convention", seed=2))


def test_render_draws_the_trial():
    env = MissionEnv(Scenario.paper("rendezvous", 2, 2, seed=0), render_mode="rgb_array")
    env.reset(seed=0)
    env.step(env.level_actions("convention"))
    image = env.render()
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
    assert image.shape[0] > 200 and len(np.unique(image.reshape(-1, 3), axis=0)) > 20
    assert MissionEnv(Scenario.paper("rendezvous", 2, 2, seed=0)).render() is None


def test_bad_use_is_refused_clearly():
    s = Scenario.paper("rendezvous", 2, 2, seed=0)
    with pytest.raises(InvalidArgumentError, match="Scenario or a mission"):
        MissionEnv("specs/rendezvous.epi")
    with pytest.raises(InvalidArgumentError, match="unknown reasoning level"):
        MissionEnv(s, teammates={"r1": "fourth"})
    with pytest.raises(InvalidArgumentError, match="teammates names robot"):
        MissionEnv(s, teammates={"r9": "zero"})
    with pytest.raises(InvalidArgumentError, match="no agent is left"):
        MissionEnv(s, teammates={"r1": "zero", "r2": "zero"})
    with pytest.raises(InvalidArgumentError, match="render_mode"):
        MissionEnv(s, render_mode="human")
    env = MissionEnv(s)
    with pytest.raises(InvalidArgumentError, match="reset"):
        env.step({})
    env.reset(seed=0)
    with pytest.raises(InvalidArgumentError, match="no action for agent"):
        env.step({"r1": np.zeros(2)})
    for bad in ([np.nan, 0.0], [1.0], "fast"):
        with pytest.raises(InvalidArgumentError, match="action of r1 must be two finite"):
            env.step({"r1": bad, "r2": np.zeros(2)})
    while env.agents:
        env.step({a: np.zeros(2) for a in env.agents})
    with pytest.raises(InvalidArgumentError, match="the trial is over"):
        env.step({})
    with pytest.raises(InvalidArgumentError, match="no robot"):
        RobotEnv(s, robot="r7")


def test_the_example_runs_a_level_and_a_random_policy(capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["example", "--trials", "3"])
    runpy.run_path(str(ROOT / "examples" / "env_level_vs_random.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert "convention: 3/3 successes" in out  # the convention solves these three trials
    assert "random: 0/3 successes" in out
