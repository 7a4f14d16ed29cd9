"""Sweeps: deterministic trial ids, resumable storage, the Dask path, the report."""

from __future__ import annotations

import hashlib
import json
import signal
import sqlite3
import subprocess
import sys
import time

import numpy as np
import pytest

from epistemica.cli import main
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.study.report import summarise, wilson_interval
from epistemica.sim.study.store import OUTCOME_COLUMNS, ResultStore, read_rows
from epistemica.sim.study.sweep import ProtocolWorld, TrialSpec, plan_sweep, run_sweep, run_trial

GRID = dict(
    missions=["rendezvous", "allocation"],
    robots=[2, 3],
    goals=None,
    reasoning=["zero", "convention"],
    trials=3,
)


def outcomes(rows):
    return sorted(tuple(r[c] for c in OUTCOME_COLUMNS) for r in rows)


def _spec(mission, robots, goals, level, seed, options=()):
    return TrialSpec(ProtocolWorld(mission, robots, goals, options), level, seed)


def test_a_trial_id_is_the_documented_hash_so_old_results_files_resume():
    spec = _spec("rendezvous", 2, 3, "zero", 4, (("sensing_range", 10.0),))
    text = json.dumps(["rendezvous", 2, 3, "zero", 4, [["sensing_range", 10.0]]], sort_keys=True)
    assert spec.id == hashlib.sha256(text.encode()).hexdigest()[:16]


def test_trial_id_depends_on_every_parameter_and_nothing_else():
    base = _spec("rendezvous", 2, 3, "zero", 4)
    assert base.id == _spec("rendezvous", 2, 3, "zero", 4).id
    variants = [
        _spec("allocation", 2, 3, "zero", 4),
        _spec("rendezvous", 3, 3, "zero", 4),
        _spec("rendezvous", 2, 2, "zero", 4),
        _spec("rendezvous", 2, 3, "rules-first", 4),
        _spec("rendezvous", 2, 3, "zero", 5),
        _spec("rendezvous", 2, 3, "zero", 4, (("sensing_range", 10.0),)),
    ]
    assert len({base.id, *(v.id for v in variants)}) == 1 + len(variants)


def test_plan_covers_the_grid_with_shared_seeds():
    specs = plan_sweep(**GRID)
    assert len(specs) == 2 * 2 * 2 * 3 and len({s.id for s in specs}) == len(specs)
    assert {s.seed for s in specs} == {0, 1, 2}
    assert all(s.goals == s.robots for s in specs)  # default: as many goals as robots


def test_plan_rejects_bad_input_before_running():
    with pytest.raises(InvalidArgumentError, match="unknown reasoning"):
        plan_sweep(["rendezvous"], [2], None, ["telepathy"], 1)
    with pytest.raises(InvalidArgumentError, match="no valid cell"):
        plan_sweep(["allocation"], [3], [2], ["zero"], 1)


def test_rows_match_a_direct_simulation(tmp_path):
    spec = _spec("allocation", 3, 3, "convention", 7)
    row = run_trial(spec)
    from epistemica.sim import simulate

    trial = simulate(spec.scenario(), "convention", seed=7)
    assert (row["success"], row["steps"]) == (int(trial.success), trial.steps)


def test_resume_runs_only_missing_trials_and_never_duplicates(tmp_path):
    path = tmp_path / "r.sqlite"
    specs = plan_sweep(**GRID)
    with ResultStore(path) as store:
        run_sweep(specs[:5], store, workers=1)
    with pytest.raises(InvalidArgumentError, match="already exists"):
        ResultStore(path)
    with ResultStore(path, resume=True) as store:
        ran, skipped = run_sweep(specs, store, workers=1)
    assert (ran, skipped) == (len(specs) - 5, 5)
    rows = read_rows(path)
    assert sorted(r["id"] for r in rows) == sorted(s.id for s in specs)


def test_local_processes_give_the_rows_of_one_process(tmp_path):
    specs = plan_sweep(**GRID)
    with ResultStore(tmp_path / "a.sqlite") as a, ResultStore(tmp_path / "b.sqlite") as b:
        run_sweep(specs, a, workers=1)
        run_sweep(specs, b, workers=2)
        assert outcomes(a.rows()) == outcomes(b.rows())


def test_sigkill_mid_sweep_then_resume(tmp_path):
    out = tmp_path / "killed.sqlite"
    command = [
        sys.executable,
        "-m",
        "epistemica",
        "sweep",
        "--mission",
        "rendezvous",
        "--robots",
        "2..3",
        "--reasoning",
        "zero,convention",
        "--trials",
        "25",  # 100 trials: killed at about 20 stored, --resume runs the rest in seconds
        "--workers",
        "1",
        "--out",
        str(out),
    ]
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.time() + 60
    stored = 0
    while time.time() < deadline and stored < 20:
        time.sleep(0.2)
        if out.exists():
            try:
                stored = sqlite3.connect(out).execute("SELECT COUNT(*) FROM trials").fetchone()[0]
            except sqlite3.OperationalError:
                stored = 0
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert 20 <= stored < 100, "the sweep must be killed mid-way"
    before = read_rows(out)
    assert subprocess.run([*command, "--resume"], capture_output=True).returncode == 0
    after = read_rows(out)
    expected = {s.id for s in plan_sweep(["rendezvous"], [2, 3], None, ["zero", "convention"], 25)}
    assert sorted(r["id"] for r in after) == sorted(expected)  # each exactly once
    kept = {r["id"]: r for r in after}
    assert all(kept[r["id"]]["steps"] == r["steps"] for r in before)


def test_dask_cluster_on_loopback_gives_identical_rows(tmp_path):
    distributed = pytest.importorskip("distributed")
    specs = plan_sweep(**GRID)
    with ResultStore(tmp_path / "local.sqlite") as local:
        run_sweep(specs, local, workers=1)
        expected = outcomes(local.rows())
    with distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        out = tmp_path / "cluster.sqlite"
        status = main(
            [
                "sweep",
                "--mission",
                "rendezvous,allocation",
                "--robots",
                "2..3",
                "--reasoning",
                "zero,convention",
                "--trials",
                "3",
                "--out",
                str(out),
                "--scheduler",
                cluster.scheduler_address,
            ]
        )
    assert status == 0
    assert outcomes(read_rows(out)) == expected


def test_a_cluster_whose_workers_all_die_ends_the_sweep_with_a_clear_error():
    """Every worker gone mid-sweep (the cluster scaled to none): the trials would wait
    for ever; the driver gives up after ``patience`` seconds without a worker."""
    distributed = pytest.importorskip("distributed")
    from epistemica.sim.study._executors import WorkersLost, run_cluster

    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        rows = run_cluster(time.sleep, iter([0.3] * 40), cluster.scheduler_address, 2, 1.0)
        assert next(rows) is None  # one trial ran (time.sleep returns None)
        cluster.scale(0)
        start = time.monotonic()
        with pytest.raises(WorkersLost, match="no worker for 1 s") as lost:
            list(rows)
        assert time.monotonic() - start < 15
        assert "--resume" in lost.value.hint


def test_a_sweep_on_a_scheduler_without_workers_exits_2(tmp_path, monkeypatch, capsys):
    distributed = pytest.importorskip("distributed")
    from epistemica.sim.study import _executors

    monkeypatch.setattr(_executors, "NO_WORKER_SECONDS", 1.0)
    with distributed.LocalCluster(
        n_workers=0, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        argv = ["sweep", "--robots", "2", "--trials", "1", "--reasoning", "zero"]
        out = str(tmp_path / "x.sqlite")
        status = main([*argv, "--out", out, "--scheduler", cluster.scheduler_address])
    assert status == 2
    err = capsys.readouterr().err
    assert "has had no worker for 1 s" in err and "Traceback" not in err


# Ctrl-C (a SIGINT to this process) while the pool forks its first worker, from an
# at-fork hook: where Python would raise it, it is printed as "Exception ignored" and lost.
# The child starts as a terminal's foreground process would: a shell's background job (CI
# run with `&`) inherits SIGINT ignored, and a held or ignored Ctrl-C is never raised.
_CTRL_C_DURING_FORK = """
import os, signal, sys
signal.signal(signal.SIGINT, signal.default_int_handler)
signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
from epistemica.sim.study._executors import run_local
fired = []
def hook():
    if not fired:
        fired.append(1)
        os.kill(os.getpid(), signal.SIGINT)
os.register_at_fork(after_in_parent=hook)
try:
    rows = list(run_local(abs, range(-20, 0), 2))
except KeyboardInterrupt:
    print("interrupted")
    sys.exit(130)
print("finished", len(rows))
"""


def test_a_ctrl_c_while_workers_fork_is_not_lost():
    done = subprocess.run(
        [sys.executable, "-c", _CTRL_C_DURING_FORK], capture_output=True, text=True, timeout=60
    )
    assert (done.returncode, done.stdout.strip()) == (130, "interrupted"), done.stderr
    assert "Exception ignored" not in done.stderr


def test_missing_dask_is_a_clear_error(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import fails
    status = main(
        [
            "sweep",
            "--robots",
            "2",
            "--trials",
            "1",
            "--reasoning",
            "zero",
            "--out",
            str(tmp_path / "x.sqlite"),
            "--scheduler",
            "tcp://127.0.0.1:1",
        ]
    )
    assert status == 2
    assert "epistemica[cluster]" in capsys.readouterr().err


def test_wilson_interval_matches_scipy():
    from scipy.stats import binomtest

    for k, n in [(0, 10), (3, 10), (45, 50), (50, 50), (1, 1)]:
        ci = binomtest(k, n).proportion_ci(method="wilson")
        assert np.allclose(wilson_interval(k, n), (ci.low, ci.high))


def test_report_table_and_figure(tmp_path, capsys):
    path = tmp_path / "r.sqlite"
    specs = plan_sweep(**GRID)
    with ResultStore(path) as store:
        run_sweep(specs, store, workers=1)
    rows = read_rows(path)
    cells = summarise(rows)
    assert len(cells) == 8 and all(c.trials == 3 for c in cells)
    for c in cells:
        mine = [
            r
            for r in rows
            if (r["mission"], r["robots"], r["reasoning"]) == (c.mission, c.robots, c.reasoning)
        ]
        assert c.successes == sum(r["success"] for r in mine)
    png = tmp_path / "fig.png"
    assert main(["report", str(path), "--markdown", "--png", str(png)]) == 0
    text = capsys.readouterr().out
    assert text.count("\n| rendezvous") == 4 and "[" in text
    image = pytest.importorskip("matplotlib.image").imread(png)
    assert image.shape[0] > 200 and image.shape[1] > 2 * image.shape[0] * 0.9  # two panels
    assert image[..., :3].std() > 0.05  # not blank


def test_report_of_missing_or_foreign_file(tmp_path, capsys):
    assert main(["report", str(tmp_path / "none.sqlite")]) == 2
    junk = tmp_path / "junk.sqlite"
    junk.write_text("not a database at all" * 50)
    assert main(["report", str(junk)]) == 2
    assert "hint" in capsys.readouterr().err
