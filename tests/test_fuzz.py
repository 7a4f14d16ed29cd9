"""The fuzz corpora in CI: mutated shipped specs and mission files, and random command lines
(check, show, plan; run, check, sweep, simulate, report), mutated SMCDEL files and EPDDL
tasks, and hostile traces for view exit with 0, 1 or 2 only, each within its time limit,
in a worker whose memory is bounded (tests/fuzz_corpus.py, tests/fuzz_missions.py and
tests/fuzz_formats.py; benchmarks/fuzz_cli.py runs the large spec corpus)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).parent


def _run(script: str, cases: int, through: int = 30) -> dict:
    out = subprocess.run(
        [sys.executable, str(HERE / script), "--cases", str(cases), "--seed", "2024",
         "--limit", "20", "--memory-gib", "3"],
        capture_output=True, text=True, timeout=110, check=False,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    result = json.loads(out.stdout)
    assert result["bad"] == [], result["bad"]
    assert sum(result["counts"].values()) == cases
    assert set(result["counts"]) <= {"0", "1", "2"}
    assert result["slowest_seconds"] < 20
    assert result["max_rss_mib"] < 3 * 1024
    # The corpus is not all refusals: unmutated cases and harmless edits run through.
    assert result["counts"].get("0", 0) + result["counts"].get("1", 0) >= through
    return result


def test_fuzzed_specs_and_parameters_exit_0_1_or_2_in_bounded_time_and_memory():
    _run("fuzz_corpus.py", 500)


def test_fuzzed_missions_and_simulator_parameters_exit_0_1_or_2_in_bounded_time():
    result = _run("fuzz_missions.py", 200)
    assert result["missions"] >= 90  # every shipped mission file is a seed of the corpus


def test_fuzzed_smcdel_epddl_and_hostile_traces_exit_0_1_or_2_in_bounded_time():
    # tests/fuzz_formats.py: a third each of SMCDEL files, EPDDL tasks and traces for view
    _run("fuzz_formats.py", 90, through=5)
