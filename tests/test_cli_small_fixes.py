"""Small promises of the command line: sweep makes its --out folder, plan --verify names
worlds as --explain does."""

from __future__ import annotations

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
