"""`epistemica simulate` and the trial pictures: exit codes, JSON, PNG and GIF read back."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from epistemica.cli import main
from epistemica.del_.errors import EpistemicaError
from epistemica.sim import Scenario, simulate
from epistemica.sim.figures import animate_trial, plot_trial

PIL = pytest.importorskip("PIL.Image")


def test_success_and_failure_exit_codes_and_json(capsys):
    # Seed 2, allocation of 4 robots: third order succeeds; greedy rendezvous of 3 fails.
    assert main(["simulate", "--mission", "allocation", "--robots", "4", "--seed", "2"]) == 0
    assert "succeeded" in capsys.readouterr().out
    status = main(
        [
            "simulate",
            "--robots",
            "3",
            "--seed",
            "0",
            "--reasoning",
            "zero",
            "--json",
            "--max-steps",
            "20",
        ]
    )
    record = json.loads(capsys.readouterr().out)
    trial = simulate(Scenario.paper("rendezvous", 3, seed=0, max_steps=20), "zero", seed=0)
    assert status == (0 if trial.success else 1)
    assert record["success"] == trial.success and record["steps"] == trial.steps
    assert record["sensors"] == list(trial_scenario_sensors(0))


def trial_scenario_sensors(seed):
    return Scenario.paper("rendezvous", 3, seed=seed).sensors


def test_bad_input_exits_2_without_traceback():
    for argv in (["--robots", "0"], ["--reasoning", "telepathy"], ["--mission", "juggle"]):
        proc = subprocess.run(
            [sys.executable, "-m", "epistemica", "simulate", *argv], capture_output=True, text=True
        )
        assert proc.returncode == 2 and "Traceback" not in proc.stderr
        assert "hint:" in proc.stderr


def test_png_has_the_map(tmp_path):
    s = Scenario.paper("allocation", 3, seed=1)
    path = tmp_path / "t.png"
    plot_trial(s, simulate(s, "convention", seed=1), path)
    image = np.asarray(PIL.open(path).convert("RGB"), dtype=float)
    assert image.shape[:2] == (640, 640)
    assert image.std() > 10  # not a blank canvas


def test_gif_frames_follow_the_trial(tmp_path):
    s = Scenario.paper("rendezvous", 2, 2, seed=3).replace(max_steps=12)
    trial = simulate(s, "third", seed=3)
    path = tmp_path / "t.gif"
    frames = animate_trial(s, trial, path)
    assert frames == min(trial.steps + 1, 60)
    with PIL.open(path) as gif:
        assert gif.n_frames == frames
        first, last = np.asarray(gif.convert("RGB")), None
        gif.seek(gif.n_frames - 1)
        last = np.asarray(gif.convert("RGB"))
    assert not np.array_equal(first, last)  # the robots moved


def test_cli_writes_both_pictures(tmp_path):
    png, gif = tmp_path / "a.png", tmp_path / "a.gif"
    main(["simulate", "--robots", "2", "--max-steps", "5", "--png", str(png), "--gif", str(gif)])
    assert png.stat().st_size > 10_000 and gif.stat().st_size > 10_000


def test_missing_matplotlib_names_the_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    s = Scenario.paper("rendezvous", 2, 2, seed=0).replace(max_steps=3)
    with pytest.raises(EpistemicaError, match="matplotlib") as err:
        plot_trial(s, simulate(s, "zero", seed=0), tmp_path / "x.png")
    assert "epistemica[plot]" in err.value.hint
