"""Results files: traces and code versions in each row, the versioned schema, reading that
never writes, claims shared by concurrent sweeps, and interruptions that lose nothing."""

from __future__ import annotations

import hashlib
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time

import numpy as np
import pytest

from epistemica.cli import main
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.provenance import code_version, package_version, source_hash
from epistemica.sim.study.store import (
    FORMAT,
    SCHEMA_VERSION,
    ResultStore,
    read_format,
    read_rows,
    read_trace,
)
from epistemica.sim.study.sweep import plan_sweep, run_sweep
from epistemica.sim.study.trace import trial_trace

SPECS = plan_sweep(["rendezvous", "allocation"], [2, 3], None, ["zero", "convention"], 2)


def _digest(path) -> str:
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def _sweep(path, specs=SPECS, traces=True):
    with ResultStore(path) as store:
        run_sweep(specs, store, workers=1, traces=traces)


def test_each_row_carries_the_trace_of_its_trial(tmp_path):
    path = tmp_path / "r.sqlite"
    _sweep(path)
    rows = {r["id"]: r for r in read_rows(path)}
    assert set(rows) == {s.id for s in SPECS}
    for spec in SPECS:
        # recomputed independently of the sweep: the same scenario and level, run again
        scenario = Scenario.paper(spec.mission, spec.robots, spec.goals, spec.seed)
        trial = simulate(scenario, spec.reasoning, seed=spec.seed)
        stored = read_trace(path, spec.id)
        assert stored == trial_trace(scenario, trial) | {"goal_belief": stored["goal_belief"]}
        assert stored["steps"] == rows[spec.id]["steps"] == trial.steps
        assert stored["success"] == bool(rows[spec.id]["success"])
        assert np.allclose(stored["goal_belief"], np.round(trial.goal_belief, 3), equal_nan=True)
        assert len(stored["poses"]) == trial.steps + 1


def test_no_traces_leaves_the_column_empty(tmp_path):
    path = tmp_path / "r.sqlite"
    _sweep(path, SPECS[:3], traces=False)
    assert [read_trace(path, s.id) for s in SPECS[:3]] == [None, None, None]
    assert main(["sweep", "--robots", "2", "--trials", "1", "--reasoning", "zero",
                 "--no-traces", "--out", str(tmp_path / "cli.sqlite")]) == 0  # fmt: skip
    (row,) = read_rows(tmp_path / "cli.sqlite")
    assert read_trace(tmp_path / "cli.sqlite", row["id"]) is None


def test_the_version_column_names_the_code_that_ran_the_trial(tmp_path):
    path = tmp_path / "r.sqlite"
    _sweep(path, SPECS[:2])
    versions = {r["version"] for r in read_rows(path)}
    assert versions == {code_version()}
    (version,) = versions
    pattern = r"(g[0-9a-f]{12}(\.dirty\.[0-9a-f]{12})?|sha\.[0-9a-f]{12})"
    assert re.fullmatch(re.escape(package_version()) + r"\+" + pattern, version)
    assert re.fullmatch(r"[0-9a-f]{12}", source_hash())
    git = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], capture_output=True,
                         text=True, cwd=os.path.dirname(__file__), check=False)  # fmt: skip
    if git.returncode == 0 and "+g" in version:
        assert version.split("+g")[1][:12] == git.stdout.strip()


def test_the_file_declares_its_format_and_schema(tmp_path):
    path = tmp_path / "r.sqlite"
    _sweep(path, SPECS[:1])
    assert read_format(path) == (FORMAT, SCHEMA_VERSION) == ("epistemica-results", 2)
    meta = dict(sqlite3.connect(path).execute("SELECT key, value FROM meta"))
    assert meta == {"format": "epistemica-results", "version": "2"}


def test_reading_never_writes_the_file(tmp_path, capsys):
    path = tmp_path / "r.sqlite"
    _sweep(path, SPECS[:4])
    before, listing = _digest(path), sorted(os.listdir(tmp_path))
    stamp = os.stat(path).st_mtime_ns
    read_rows(path)
    read_trace(path, SPECS[0].id)
    assert main(["report", str(path), "--no-png"]) == 0
    assert (_digest(path), sorted(os.listdir(tmp_path)), os.stat(path).st_mtime_ns) == (
        before,
        listing,
        stamp,
    )


def test_a_results_file_in_a_read_only_folder_is_read(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    _sweep(folder / "r.sqlite", SPECS[:4])
    folder.chmod(0o555)
    try:
        if os.access(folder, os.W_OK):
            pytest.skip("running as a user who writes anywhere")
        assert len(read_rows(folder / "r.sqlite")) == 4
    finally:
        folder.chmod(0o755)


@pytest.mark.parametrize("kind", ["garbage", "foreign", "empty-database", "null", "type"])
def test_a_foreign_or_damaged_file_is_refused_and_left_alone(tmp_path, kind, capsys):
    path = tmp_path / "x.sqlite"
    if kind == "garbage":
        path.write_bytes(b"not a database" * 100)
    elif kind == "empty-database":
        sqlite3.connect(path).execute("PRAGMA user_version = 1").connection.commit()
    elif kind == "foreign":
        db = sqlite3.connect(path)
        db.execute("CREATE TABLE people (name TEXT)")
        db.commit()
    elif kind == "null":  # a file written by other software, without constraints
        _sweep(tmp_path / "good.sqlite", SPECS[:2])
        db = sqlite3.connect(path)
        db.execute("ATTACH ? AS good", (str(tmp_path / "good.sqlite"),))
        db.execute("CREATE TABLE trials AS SELECT * FROM good.trials")
        db.execute("UPDATE trials SET success = NULL")
        db.commit()
        db.close()
    else:
        _sweep(path, SPECS[:2])
        db = sqlite3.connect(path)
        db.execute("UPDATE trials SET steps = 'many'")
        db.commit()
        db.close()
    before = _digest(path)
    with pytest.raises(InvalidArgumentError, match="not an epistemica results file"):
        read_rows(path)
    assert main(["report", str(path), "--no-png"]) == 2
    assert "Traceback" not in capsys.readouterr().err
    assert _digest(path) == before


def test_a_schema_1_file_is_read_and_upgraded_when_resumed(tmp_path):
    path = tmp_path / "old.sqlite"
    old_columns = [c for c in ResultStore.__init__.__globals__["COLUMNS"] if c != "trace"]
    db = sqlite3.connect(path)
    db.execute(f"CREATE TABLE trials ({', '.join(old_columns)})")
    row = {c: None for c in old_columns} | {
        "id": "t0", "mission": "rendezvous", "robots": 2, "goals": 2, "reasoning": "zero",
        "seed": 0, "options": "{}", "success": 1, "steps": 9, "wall_time": 0.1,
        "decision_ms": 0.1, "considered": 1.0, "version": "0.1.0",
    }  # fmt: skip
    db.execute(f"INSERT INTO trials VALUES ({', '.join('?' * len(old_columns))})",
               [row[c] for c in old_columns])  # fmt: skip
    db.commit()
    db.close()
    assert read_format(path) == (FORMAT, 1)
    assert read_rows(path)[0]["steps"] == 9
    with ResultStore(path, resume=True) as store:
        run_sweep(SPECS[:1], store, workers=1)
    assert read_format(path) == (FORMAT, 2)
    assert read_trace(path, "t0") is None and read_trace(path, SPECS[0].id) is not None


def test_an_empty_file_left_by_a_failed_sweep_does_not_block_the_rerun(tmp_path):
    path = tmp_path / "r.sqlite"
    path.touch()
    _sweep(path, SPECS[:1])
    assert len(read_rows(path)) == 1
    with pytest.raises(InvalidArgumentError, match="already exists"):
        ResultStore(path)


def test_claims_keep_two_stores_off_each_others_trials(tmp_path):
    path = tmp_path / "r.sqlite"
    with ResultStore(path) as first, ResultStore(path, resume=True) as second:
        assert first.claim("t1") and not second.claim("t1")
        assert second.claim("t2") and not first.claim("t2")
        assert first.claimed_elsewhere() == 1
        first.release()
        assert second.claim("t1")
    # the claim of a process that died is taken over
    db = sqlite3.connect(path)
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True).stdout.strip()  # fmt: skip
    host = ResultStore(path, resume=True)
    owner = f"{host.owner.rsplit(':', 2)[0]}:{dead}:gone"
    db.execute("INSERT INTO claims VALUES ('t3', ?, ?)", (owner, time.time()))
    db.commit()
    assert host.claim("t3")
    host.close()


def _counts(output: str) -> int:
    return int(re.search(r"(\d+) trials run", output).group(1))


def test_concurrent_sweeps_on_one_file_share_the_trials(tmp_path):
    out = tmp_path / "shared.sqlite"
    args = [sys.executable, "-m", "epistemica", "sweep", "--mission", "allocation",
            "--robots", "2..3", "--reasoning", "zero,convention", "--trials", "12",
            "--workers", "1", "--out", str(out)]  # fmt: skip
    ResultStore(out).close()  # both open it with --resume
    runs = [subprocess.Popen([*args, "--resume"], stdout=subprocess.PIPE, text=True)
            for _ in range(2)]  # fmt: skip
    outputs = [run.communicate(timeout=240)[0] for run in runs]
    assert [run.returncode for run in runs] == [0, 0]
    ran = [_counts(o) for o in outputs]
    expected = {s.id for s in plan_sweep(["allocation"], [2, 3], None, ["zero", "convention"], 12)}
    assert {r["id"] for r in read_rows(out)} == expected
    assert sum(ran) == len(expected), ran  # no trial ran twice
    assert min(ran) > 0, ran  # and both did some


def _children(pid: int) -> list[int]:
    found = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True)
    return [int(p) for p in found.stdout.split()]


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


#: Trials per team size of the interrupted sweeps: seconds of work left when the test acts
#: (3 stored), and little to finish on --resume.
SWEEP_TRIALS = 15


def _start_sweep(out, extra=()):
    args = [sys.executable, "-m", "epistemica", "sweep", "--mission", "allocation", "--robots",
            "4..5", "--reasoning", "rules-third", "--trials", str(SWEEP_TRIALS), "--workers", "2",
            "--out", str(out), *extra]  # fmt: skip
    # A process started in the background of a non-interactive shell inherits SIGINT
    # ignored, and Python then keeps ignoring it: give the sweep the default, as a terminal.
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=_default_sigint)  # fmt: skip
    deadline = time.time() + 120
    while time.time() < deadline:
        time.sleep(0.3)
        try:
            db = sqlite3.connect(f"file:{out}?mode=ro", uri=True)
            if db.execute("SELECT COUNT(*) FROM trials").fetchone()[0] >= 3:
                return proc, args
        except sqlite3.Error:
            pass
    proc.kill()
    pytest.fail("the sweep stored nothing in 120 s")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_ctrl_c_returns_at_once_with_every_finished_trial_stored(tmp_path):
    out = tmp_path / "int.sqlite"
    proc, args = _start_sweep(out)
    workers = _children(proc.pid)
    assert len(workers) == 2
    started = time.monotonic()
    os.killpg(proc.pid, signal.SIGINT)  # as a terminal does: the whole group
    _, err = proc.communicate(timeout=30)
    seconds = time.monotonic() - started
    assert proc.returncode == 130 and seconds < 2.0, (proc.returncode, seconds)
    stored = len(read_rows(out))
    total = 2 * SWEEP_TRIALS
    assert f"interrupted: {stored} of {total} trials stored" in err and "Traceback" not in err
    time.sleep(1.0)
    assert not [w for w in workers if _alive(w)]
    done = subprocess.run([*args, "--resume", "--workers", "1"], capture_output=True, text=True)
    assert done.returncode == 0 and f"{total - stored} trials run, {stored} already" in done.stdout


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_workers_die_with_their_parent_after_kill_9(tmp_path):
    proc, _ = _start_sweep(tmp_path / "k.sqlite")
    workers = _children(proc.pid)
    assert workers
    proc.kill()
    proc.wait()
    deadline = time.monotonic() + 3.0
    while time.monotonic() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.05)
    assert not [w for w in workers if _alive(w)], "workers outlived their parent by 3 s"


def test_sweeps_opening_and_closing_one_file_at_once_wait_for_each_other(tmp_path):
    # Opening switches the file to write-ahead logging and closing switches it back: both
    # take the file exclusively, and SQLite does not wait for that. Three processes
    # opening and closing one file 30 times each all succeed (before: "database is
    # locked" within a few rounds).
    path = tmp_path / "busy.sqlite"
    ResultStore(path).close()
    script = (
        "import sys\nfrom epistemica.sim.study.store import ResultStore\n"
        "for _ in range(30):\n    ResultStore(sys.argv[1], resume=True).close()\n"
    )
    runs = [subprocess.Popen([sys.executable, "-c", script, str(path)], stderr=subprocess.PIPE,
                             text=True) for _ in range(3)]  # fmt: skip
    errors = [run.communicate(timeout=240)[1] for run in runs]
    assert [run.returncode for run in runs] == [0, 0, 0], errors


def test_resume_into_another_studys_file_is_refused(tmp_path, capsys):
    out = str(tmp_path / "a" / "r.sqlite")  # a missing folder is created for --out
    sweep = ["sweep", "--robots", "2", "--trials", "1", "--reasoning", "zero", "--out", out]
    assert main([*sweep, "--workers", "1"]) == 0
    before = read_rows(out)
    # the same study resumes (nothing to run); a study sharing no trial is refused
    assert main([*sweep, "--workers", "1", "--resume"]) == 0
    assert main([*sweep, "--workers", "1", "--resume", "--seed", "7"]) == 2
    assert "none of them this study's" in capsys.readouterr().err
    assert read_rows(out) == before
