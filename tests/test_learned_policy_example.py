"""examples/learned_policy.py at a tiny budget: it trains, and reports the learned policy
beside the reasoning levels on the study's seeds (skipped without the learn extra); its
egocentric features and its learning curve against values computed here."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.distance import pdist

pytest.importorskip("stable_baselines3")  # the learn extra (needs torch): not in CI's test
pytest.importorskip("pettingzoo")

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.env import MissionEnv

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "learned_policy.py"
RENDEZVOUS = ROOT / "specs" / "rendezvous.epi"


def test_the_example_trains_and_reports_beside_the_levels(capsys, monkeypatch):
    argv = ["learned_policy", str(RENDEZVOUS), "--timesteps", "48", "--eval", "2", "--copies", "1"]
    monkeypatch.setattr(sys, "argv", argv)
    runpy.run_path(str(EXAMPLE), run_name="__main__")
    out = capsys.readouterr().out.splitlines()
    mission = load_mission(RENDEZVOUS)
    seeds = [mission.study.seed, mission.study.seed + 1]
    table = out.index(next(line for line in out if line.startswith("level ")))
    rows = {line.split()[0]: line.split()[1] for line in out[table + 1 :]}
    for level in mission.study.levels:
        won = sum(
            simulate(mission.scenario(s), level, seed=s, policies=mission.policies(s),
                     parameters=mission.parameters).success
            for s in seeds
        )  # fmt: skip
        assert rows[level] == f"{won}/2"
    learned = next(line for line in out if line.startswith("learned (PPO)"))
    assert learned.split()[2].endswith("/2")
    assert "48 robot-steps" in out[0]
    assert all(line.startswith("curve") for line in out[1:table])


def test_egocentric_features_are_offsets_in_the_robot_frame():
    example = runpy.run_path(str(EXAMPLE))
    env = MissionEnv(load_mission(RENDEZVOUS), epistemic=True, normalized=True)
    views, _ = env.reset(seed=10_003)
    features = example["Features"](env, egocentric=True)
    s, view = env.scenario, views["r2"]
    vector = features(view)
    assert vector.shape == features.box.shape
    x, y, h = (float(v) for v in view["pose"])
    ahead, left = np.array([np.cos(h), np.sin(h)]), np.array([-np.sin(h), np.cos(h)])
    start = 4 + 3 * s.n_robots  # own (x, y, cos, sin), then a row per robot
    for g, goal in enumerate(s.goals):
        d = goal - np.array([x, y])
        expected = [d @ ahead, d @ left, np.linalg.norm(d)]
        got = vector[start + 3 * g : start + 3 * g + 3]
        np.testing.assert_allclose(got, np.array(expected) / s.workspace, atol=1e-5)
    mate = view["teammates"][0] - np.array([x, y])  # where r2 places r1
    np.testing.assert_allclose(vector[4:6], [mate @ ahead / 30, mate @ left / 30], atol=1e-5)
    np.testing.assert_allclose(vector[7:9], [0, 0], atol=1e-6)  # its own row
    assert vector[-1] == pytest.approx(view["step"] / s.max_steps)


def test_the_learning_curve_averages_equal_slices_in_order():
    curve = runpy.run_path(str(EXAMPLE))["learning_curve"]
    episodes = [(float(k), k % 3 == 0) for k in range(10)]
    rows = curve(episodes, points=2)
    assert rows == [(5, 2.0, 2 / 5), (10, 7.0, 2 / 5)]  # 0..4: 0, 3 won; 5..9: 6, 9
    assert curve([], points=4) == []
    assert [r[0] for r in curve(episodes[:3], points=10)] == [1, 2, 3]


def test_the_gather_shaping_starts_at_minus_the_mean_gap_between_robots():
    example = runpy.run_path(str(EXAMPLE))
    mission = load_mission(RENDEZVOUS)
    env = example["SharedPolicyEnv"](mission, 2, True, 1.0, gather=1.0)
    obs = env.reset()
    assert obs.shape == (2 * 3, env.features.box.shape[0])
    for k in range(len(env.envs)):
        start = mission.scenario(10_000 + k).starts[:, :2]
        assert env.spread[k] == pytest.approx(-pdist(start).mean() / 30, rel=1e-5)
    assert example["SharedPolicyEnv"](mission, 1, True, 1.0).reset().shape == (3, obs.shape[1])


def test_the_meeting_goal_is_the_goal_every_robot_ended_at():
    meeting_goal = runpy.run_path(str(EXAMPLE))["meeting_goal"]
    mission = load_mission(RENDEZVOUS)
    for seed in (0, 1, 2):
        s = mission.scenario(seed)
        trial = simulate(s, "rules-third", seed=seed)
        assert trial.success
        ends = trial.trajectory[-1, :, :2]
        near = [
            g
            for g, goal in enumerate(s.goals)
            if (np.hypot(*(ends - goal).T) <= s.success_radius).all()
        ]
        assert meeting_goal(s, trial) == near[0]
    zero = (simulate(mission.scenario(seed), "zero", seed=seed) for seed in range(20))
    failed = next(t for t in zero if not t.success)
    assert meeting_goal(mission.scenario(failed.seed), failed) is None


def test_a_saved_model_loads_with_its_normalisation(monkeypatch, tmp_path):
    example = runpy.run_path(str(EXAMPLE))
    saved, mission = str(tmp_path / "model"), load_mission(RENDEZVOUS)
    argv = [str(RENDEZVOUS), "--timesteps", "96", "--copies", "1", "--load", saved]
    monkeypatch.setattr(sys, "argv", ["learned_policy", *argv])
    args = example["arguments"]()
    model, env, normalizer = example["train"](args, mission)
    model.save(f"{saved}.zip")
    normalizer.save(f"{saved}.pkl")
    loaded, _, restored = example["restore"](args, mission)
    assert not restored.training
    np.testing.assert_array_equal(restored.obs_rms.mean, normalizer.obs_rms.mean)
    assert normalizer.obs_rms.count > 1  # the statistics moved in training
    raw = env.reset()
    np.testing.assert_array_equal(restored.normalize_obs(raw), normalizer.normalize_obs(raw))
    mine, _ = model.predict(normalizer.normalize_obs(raw), deterministic=True)
    theirs, _ = loaded.predict(restored.normalize_obs(raw), deterministic=True)
    np.testing.assert_allclose(mine, theirs, atol=1e-6)
