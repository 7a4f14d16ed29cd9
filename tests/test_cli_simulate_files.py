"""``simulate``: the names of the mission (r1.., g1..), mission files, what it wrote."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from epistemica.cli import main
from epistemica.mission import load_mission
from epistemica.sim import Scenario, simulate

ROOT = Path(__file__).resolve().parents[1]
PRIVATE = ROOT / "specs" / "nested" / "private_goal_3.epi"


def test_text_names_robots_and_goals_as_the_pictures_do(capsys):
    assert main(["simulate", "--mission", "allocation", "--robots", "3", "--seed", "2"]) in (0, 1)
    lines = capsys.readouterr().out.splitlines()[1:]
    s = Scenario.paper("allocation", 3, seed=2)
    trial = simulate(s, "rules-third", seed=2)
    for i, line in enumerate(lines):
        words = line.split()
        assert words[0] == s.robot_names[i] == f"r{i + 1}"
        goal = trial.focal[-1, i, i]
        assert words[5] == (s.goal_names[goal] if goal >= 0 else "-")


def test_a_mission_file_is_simulated_as_run_simulates_it(tmp_path, capsys, few_frames):
    gif = tmp_path / "t.gif"
    argv = ["simulate", "--mission", str(PRIVATE), "--seed", "4", "--reasoning", "rules-first"]
    status = main([*argv, "--gif", str(gif)])
    out = capsys.readouterr().out
    mission = load_mission(PRIVATE)
    trial = simulate(mission.scenario(4), "rules-first", seed=4, parameters=mission.parameters)
    assert status == (0 if trial.success else 1)
    verdict = f"succeeded at step {trial.steps}" if trial.success else "failed within"
    assert (verdict in out and "r1  bearing" in out) or "r1  range" in out
    assert f"animation: {gif} (" in out and gif.read_bytes()[:3] == b"GIF"
    # Without --reasoning, the study's last level.
    assert main(["simulate", "--mission", str(PRIVATE), "--seed", "4"]) in (0, 1)
    assert " third " in capsys.readouterr().out


def test_a_collaborative_mission_file_is_simulated_and_drawn(tmp_path, capsys, few_frames):
    path = ROOT / "specs" / "collaborative" / "tasks_3.epi"
    png, gif = tmp_path / "t.png", tmp_path / "t.gif"
    argv = ["simulate", "--mission", str(path), "--seed", "1", "--reasoning", "rules"]
    status = main([*argv, "--png", str(png), "--gif", str(gif)])
    out = capsys.readouterr().out.splitlines()
    mission = load_mission(path)
    s = mission.scenario(1)
    trial = simulate(
        s, "rules", seed=1, policies=mission.policies(1), parameters=mission.parameters
    )
    assert status == (0 if trial.success else 1)
    verdict = f"succeeded at step {trial.steps}" if trial.success else "failed within"
    assert f"with 3 robots and {s.n_tasks} tasks, seed 1: {verdict}" in out[2]
    doing = {-1: "exploring", -2: "fetching", -3: "waiting"}
    for i, line in enumerate(out[3:6]):
        target = int(trial.steer_to[-1, i])
        words = line.split()
        assert words[:3] == [s.robot_names[i], s.sensors[i], "rules"]
        expected = doing.get(target) or f"steering to {s.task_names[target]}"
        assert " ".join(words[3:]).startswith(expected)
        x, y = trial.trajectory[-1, i, :2]
        assert line.endswith(f"at ({x:.1f}, {y:.1f})")
    done = trial.completion_step
    assert (f"  all tasks done at step {done}" in out) == (done is not None)
    assert png.read_bytes()[:4] == b"\x89PNG" and gif.read_bytes()[:3] == b"GIF"
    assert main([*argv, "--json"]) == status
    record = json.loads(capsys.readouterr().out)
    assert (record["mission"], record["robots"], record["goals"]) == ("collaborative", 3, s.n_tasks)
    assert record["steps"] == trial.steps and record["sensors"] == list(s.sensors)


@pytest.mark.parametrize("json_flag", [["--json"]])
def test_json_output_stays_json_with_pictures(tmp_path, capsys, json_flag):
    import json

    png = tmp_path / "t.png"
    main(["simulate", "--robots", "2", "--png", str(png), *json_flag])
    assert json.loads(capsys.readouterr().out)["format"] == "epistemica-simulate"
