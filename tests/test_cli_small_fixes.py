"""Small promises of the command line: sweep makes its --out folder, plan --verify names
worlds as --explain does."""

from __future__ import annotations

import json
import re
import sqlite3
from pathlib import Path

from epistemica.cli import main

ROOT = Path(__file__).resolve().parents[1]


def test_sweep_into_a_fresh_folder_creates_it(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["sweep", "--robots", "2", "--trials", "1", "--out", "runs/x.sqlite"]) == 0
    rows = sqlite3.connect(tmp_path / "runs" / "x.sqlite").execute("SELECT COUNT(*) FROM trials")
    assert rows.fetchone()[0] == 3
    assert main(["sweep", "--robots", "2", "--trials", "1", "--out", "/proc/none/x.sqlite"]) == 2
    assert "cannot create the folder /proc/none" in capsys.readouterr().err


def test_plan_verify_names_the_worlds_explain_shows(capsys):
    spec = str(ROOT / "specs" / "planning" / "sally_anne.epi")
    assert main(["plan", spec, "--verify", "sally_returns", "--explain"]) == 1
    out = capsys.readouterr().out
    shown = set(re.findall(r"\*\s+(\S+)\s+\{", out))  # the designated worlds of the state
    failing = re.search(r"at designated world\(s\) (.+)$", out, re.M).group(1).split(", ")
    assert failing and set(failing) <= shown


PRIVATE = str(ROOT / "specs" / "nested" / "private_goal_3.epi")


def test_a_question_on_a_multi_pointed_mission_is_answered_neither(capsys):
    # A rendezvous of 4 goals: one designated configuration per meeting goal, and
    # "no robot goes to g1" holds in every one but the meeting at g1.
    assert main(["check", PRIVATE, "--formula", "closed(g1)"]) == 0
    out = capsys.readouterr().out
    assert "neither  --formula: closed(g1)" in out
    assert "neither: true in 3 of 4 designated configurations" in out
    assert "closed(g1): no robot goes to g1 (~assigned(r1, g1)" in out
    assert main(["check", PRIVATE, "--formula", "~closed(g1)", "--json"]) == 0
    (claim,) = json.loads(capsys.readouterr().out)["claims"]
    assert (claim["true_in"], claim["designated"], claim["holds"]) == (1, 4, False)
    assert main(["check", PRIVATE, "--formula", "closed(g1) | ~closed(g1)"]) == 0
    assert "true (in all 4 designated configurations)" in capsys.readouterr().out


def test_a_question_on_a_symbolic_mission_model_counts_its_configurations(capsys):
    # Ten robots, ten goals: the symbolic backend; 10! designated allocations.
    path = str(ROOT / "specs" / "stress" / "allocation_adhoc_greedy_10.epi")
    assert main(["check", path, "--formula", "assigned(r1, g1)"]) == 0
    out = capsys.readouterr().out
    assert "neither: true in 362880 of 3628800 designated configurations" in out  # 9! of 10!
