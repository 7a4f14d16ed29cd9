"""A mission file swept over team sizes (robots ``r1..rN``), ``run`` with ``--resume`` and
``--scheduler``, and the smaller defects of the simulator's commands, each pinned."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from epistemica.aif.configurations import valid_configurations
from epistemica.cli import main
from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.mission import load_mission, parse_mission
from epistemica.run import MissionWorld, team_trials
from epistemica.sim import Scenario
from epistemica.sim.study.store import read_rows

ROOT = Path(__file__).resolve().parents[1]

TEAM = """\
mission rendezvous
workspace 30
robot r1..rN: random at random
goal g1..gN at random
sensing noise 0.5 model paper
check "nobody knows where": ~K[r1] assigned(r1, g1)
simulate robots 3 trials 2 seed 4 steps 80 levels zero, convention
"""


@pytest.fixture
def team(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "team.epi"
    path.write_text(TEAM)
    return path


def test_n_is_the_team_size_of_every_span(team):
    for n in (2, 5, 12):
        mission = load_mission(team, n)
        assert mission.robots == tuple(f"r{i}" for i in range(1, n + 1))
        assert mission.goals == tuple(f"g{i}" for i in range(1, n + 1))
        assert mission.team == n and mission.scenario(0).n_robots == n
    assert load_mission(team).team == 3  # the simulate line's default
    assert parse_mission(TEAM.replace("robot r1..rN", "robot r1..r3")).team == 3  # goals
    assert parse_mission(TEAM.replace("N", "3")).team is None  # no parameter


def test_n_without_a_value_is_a_located_error():
    text = TEAM.replace("simulate robots 3 ", "simulate ")
    with pytest.raises(SpecError) as caught:
        parse_mission(text, "t.epi")
    assert caught.value.line == 3 and "team size N" in str(caught.value)
    assert "--robots 2..8" in caught.value.hint


def test_trial_ids_differ_by_team_size_and_match_across_runs(team):
    ids = {n: {s.id for s in team_trials(team, [n])} for n in (2, 3, 4)}
    assert all(len(v) == 4 for v in ids.values())  # 2 levels x 2 trials
    assert not (ids[2] & ids[3]) and not (ids[3] & ids[4])
    assert ids[3] == {s.id for s in team_trials(team, [3])}
    world = MissionWorld(TEAM, str(team), 4)
    assert world.robots == world.goals == 4


def test_sweep_a_mission_file_over_team_sizes(team, capsys):
    out = team.parent / "team.sqlite"
    assert main(["sweep", "--mission", str(team), "--robots", "2..4", "--out", str(out),
                 "--workers", "1"]) == 0  # fmt: skip
    rows = read_rows(out)
    assert sorted({(r["robots"], r["goals"]) for r in rows}) == [(2, 2), (3, 3), (4, 4)]
    assert len(rows) == 3 * 2 * 2  # sizes x the file's levels x its trials
    assert {r["seed"] for r in rows} == {4, 5}  # the file's seeds
    assert {json.loads(r["options"])["spec"] for r in rows} == {"team"}
    # the same trials as `run` at the default size: a stored row is the same result
    assert main(["run", str(team), "--no-gif", "--out", str(out), "--resume"]) == 0
    assert "0 trials run, 4 already stored" in capsys.readouterr().out


def test_sweep_refuses_a_file_without_the_parameter_and_foreign_options(team, capsys):
    fixed = team.parent / "fixed.epi"
    fixed.write_text(TEAM.replace("N", "3"))
    out = str(team.parent / "x.sqlite")
    assert main(["sweep", "--mission", str(fixed), "--robots", "2..3", "--out", out]) == 2
    assert "does not declare its team size" in capsys.readouterr().err
    assert main(["sweep", "--mission", str(team), "--goals", "3", "--out", out]) == 2
    assert "--goals applies to the built-in missions" in capsys.readouterr().err
    assert main(["sweep", "--mission", f"{team},rendezvous", "--out", out]) == 2
    assert main(["sweep", "--mission", str(team), "--robots", "13", "--out", out]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_run_resume_adds_to_an_explicit_out(team, capsys):
    out = str(team.parent / "r.sqlite")
    assert main(["run", str(team), "--no-gif", "--out", out, "--trials", "1"]) == 0
    assert main(["run", str(team), "--no-gif", "--out", out, "--trials", "2"]) == 2
    assert "add --resume" in capsys.readouterr().err
    assert main(["run", str(team), "--no-gif", "--out", out, "--trials", "2", "--resume"]) == 0
    assert "2 trials run, 2 already stored, 4 of this study" in capsys.readouterr().out


def test_run_on_a_dask_cluster_stores_the_same_outcomes(team, capsys):
    distributed = pytest.importorskip("distributed")
    local = str(team.parent / "local.sqlite")
    assert main(["run", str(team), "--no-gif", "--out", local, "--workers", "1"]) == 0
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:  # fmt: skip
        remote = str(team.parent / "remote.sqlite")
        args = ["run", str(team), "--no-gif", "--out", remote]
        assert main([*args, "--scheduler", cluster.scheduler_address]) == 0

    def outcomes(path):
        return sorted((r["id"], r["success"], r["steps"]) for r in read_rows(path))

    assert outcomes(local) == outcomes(remote)


def test_check_formula_is_a_question_unless_expect_makes_it_a_claim(team, capsys):
    formula = ["--formula", "K[r1] assigned(r1, g1)"]
    assert main(["check", str(team), *formula]) == 0
    out = capsys.readouterr().out
    assert "false" in out and "FAIL" not in out and "failed" not in out
    assert main(["check", str(team), *formula, "--expect", "true"]) == 1
    assert "FAIL" in capsys.readouterr().out
    assert main(["check", str(team), *formula, "--expect", "false"]) == 0
    capsys.readouterr()
    assert main(["check", str(team), *formula, "--json"]) == 0
    (claim,) = json.loads(capsys.readouterr().out)["claims"]
    assert claim["expected"] is None and claim["ok"] is None and claim["holds"] is False


def test_check_formula_on_a_spec_file_is_a_question_too(capsys):
    coin = str(ROOT / "specs" / "puzzles" / "coin_toss.epi")  # heads is false at the start
    assert main(["check", coin, "--formula", "heads"]) == 0
    assert main(["check", coin, "--formula", "heads", "--expect", "true"]) == 1
    assert main(["check", coin, "--formula", "heads", "--expect", "false"]) == 0
    assert main(["check", coin, "--formula", "[toss] heads", "--expect", "true"]) == 0
    with pytest.raises(SystemExit) as usage:
        main(["check", coin, "--formula", "heads", "--expect", "maybe"])
    assert usage.value.code == 2


def test_report_help_prints_a_single_percent_sign(capsys):
    with pytest.raises(SystemExit):
        main(["report", "--help"])
    text = capsys.readouterr().out
    assert "95 % Wilson" in text and "%%" not in text


def test_gif_to_a_missing_folder_fails_before_the_trial(tmp_path, monkeypatch, capsys):
    def no_trial(*args, **kwargs):
        raise AssertionError("the trial ran before the path was checked")

    monkeypatch.setattr("epistemica.cli.simulate.simulate", no_trial)
    missing = tmp_path / "missing" / "dir" / "x.gif"
    assert main(["simulate", "--robots", "2", "--gif", str(missing)]) == 2
    err = capsys.readouterr().err
    assert re.search(r"--gif .*x\.gif: the folder .*dir does not exist", err)
    assert main(["simulate", "--robots", "2", "--png", str(tmp_path)]) == 2  # a folder


def test_step_limits_a_trial_cannot_allocate_are_refused(capsys):
    assert main(["simulate", "--robots", "2", "--max-steps", str(10**12)]) == 2
    assert "at most 100,000" in capsys.readouterr().err


def test_a_tiny_workspace_with_every_goal_placed_is_a_mission(tmp_path, capsys):
    path = tmp_path / "w.epi"
    path.write_text("mission rendezvous\nworkspace 1\nrobot r1: range at (0.5, 0.5)\n"
                    "goal g1 at (0.6, 0.6)\n")  # fmt: skip
    assert main(["check", str(path)]) == 0  # found by the fuzz corpus: was exit 3
    path.write_text("mission rendezvous\nworkspace 1\nrobot r1: range at (0.5, 0.5)\n"
                    "goal g1 at random\n")  # fmt: skip
    assert main(["check", str(path)]) == 2
    assert "leaves no room for goals at random" in capsys.readouterr().err


def test_seeds_and_trial_counts_a_results_file_cannot_hold_are_refused(tmp_path, capsys):
    out = str(tmp_path / "s.sqlite")
    assert main(["sweep", "--seed", str(2**80), "--trials", "1", "--out", out]) == 2
    assert main(["sweep", "--trials", str(10**12), "--out", out]) == 2
    with pytest.raises(SystemExit) as usage:  # argparse's own usage error
        main(["sweep", "--workers", "-1", "--out", out])
    assert usage.value.code == 2
    assert main(["sweep", "--scheduler", "bogus", "--trials", "1", "--out", out]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_teams_and_configuration_sets_too_large_to_list_are_refused():
    # found by the mission fuzz corpus: 13-robot protocol scenarios and the paper-first
    # level on 12 robots ran out of memory (exit 3) or for minutes
    with pytest.raises(InvalidArgumentError, match="at most 12"):
        Scenario.paper("rendezvous", 1000)
    with pytest.raises(InvalidArgumentError, match="479,001,600 configurations"):
        valid_configurations("allocation", 12, 12)  # 12! rows
    with pytest.raises(InvalidArgumentError, match="too many to list"):
        valid_configurations("allocation", 12, 64)  # was a 13.6 GiB allocation
    assert len(valid_configurations("allocation", 5, 7)) == 7 * 6 * 5 * 4 * 3
    assert len(valid_configurations("capacity", 4, 2, [2, 2])) == 6  # 4! / (2! 2!)
    assert main(["simulate", "--robots", "13"]) == 2
    # paper-first on 12 robots now samples 200 allocations, as the released multitask code
    # does from 5 robots on, instead of listing all 12!: it runs (exit 1: not done in 3 steps)
    assert main(["simulate", "--mission", "multitask", "--robots", "12",
                 "--reasoning", "paper-first", "--max-steps", "3"]) == 1  # fmt: skip
