"""The shipped stress suite is what its generator writes, and the generator's command line
writes nothing when asked for help or a check."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import stress_suite


def test_the_shipped_files_are_the_generators_text():
    assert stress_suite.main(["--check"]) == 0


def test_check_reports_a_stale_file_and_writes_nothing(tmp_path, capsys):
    assert stress_suite.main(["--out", str(tmp_path)]) == 0
    stale = tmp_path / "allocation_hardest_8.epi"
    stale.write_text("mission allocation\n")
    assert stress_suite.main(["--out", str(tmp_path), "--check"]) == 1
    assert "1 of 110 files differ" in capsys.readouterr().out
    assert stale.read_text() == "mission allocation\n"


def test_help_writes_nothing(tmp_path):
    with pytest.raises(SystemExit) as stop:
        stress_suite.main(["--out", str(tmp_path), "--help"])
    assert stop.value.code == 0
    assert not list(tmp_path.iterdir())
