"""examples/learned_policy.py at a tiny budget: it trains, and reports the learned policy
beside the reasoning levels on the study's seeds (skipped without the learn extra)."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")  # the learn extra (needs torch): not in CI's test
pytest.importorskip("pettingzoo")

from epistemica.mission import load_mission
from epistemica.sim import simulate

ROOT = Path(__file__).resolve().parents[1]


def test_the_example_trains_and_reports_beside_the_levels(capsys, monkeypatch):
    path = ROOT / "specs" / "rendezvous.epi"
    argv = ["learned_policy", str(path), "--timesteps", "48", "--eval", "2", "--copies", "1"]
    monkeypatch.setattr(sys, "argv", argv)
    runpy.run_path(str(ROOT / "examples" / "learned_policy.py"), run_name="__main__")
    out = capsys.readouterr().out.splitlines()
    mission = load_mission(path)
    seeds = [mission.study.seed, mission.study.seed + 1]
    rows = {line.split()[0]: line.split()[1] for line in out[2:]}
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
