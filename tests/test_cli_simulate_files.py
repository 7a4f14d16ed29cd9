"""``simulate``: the names of the mission (r1.., g1..), mission files, what it wrote."""

from __future__ import annotations

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
    trial = simulate(s, "third", seed=2)
    for i, line in enumerate(lines):
        words = line.split()
        assert words[0] == s.robot_names[i] == f"r{i + 1}"
        goal = trial.focal[-1, i, i]
        assert words[5] == (s.goal_names[goal] if goal >= 0 else "-")


def test_a_mission_file_is_simulated_as_run_simulates_it(tmp_path, capsys):
    gif = tmp_path / "t.gif"
    argv = ["simulate", "--mission", str(PRIVATE), "--seed", "4", "--reasoning", "first"]
    status = main([*argv, "--gif", str(gif)])
    out = capsys.readouterr().out
    mission = load_mission(PRIVATE)
    trial = simulate(mission.scenario(4), "first", seed=4, parameters=mission.parameters)
    assert status == (0 if trial.success else 1)
    verdict = f"succeeded at step {trial.steps}" if trial.success else "failed within"
    assert (verdict in out and "r1  bearing" in out) or "r1  range" in out
    assert f"animation: {gif} (" in out and gif.read_bytes()[:3] == b"GIF"
    # Without --reasoning, the study's last level.
    assert main(["simulate", "--mission", str(PRIVATE), "--seed", "4"]) in (0, 1)
    assert " third " in capsys.readouterr().out


def test_a_collaborative_mission_file_is_sent_to_run(capsys):
    path = ROOT / "specs" / "collaborative" / "tasks_3.epi"
    assert main(["simulate", "--mission", str(path)]) == 2
    assert "epistemica run" in capsys.readouterr().err


@pytest.mark.parametrize("json_flag", [["--json"]])
def test_json_output_stays_json_with_pictures(tmp_path, capsys, json_flag):
    import json

    png = tmp_path / "t.png"
    main(["simulate", "--robots", "2", "--png", str(png), *json_flag])
    assert json.loads(capsys.readouterr().out)["format"] == "epistemica-simulate"
