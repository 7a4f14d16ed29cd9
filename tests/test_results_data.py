"""Results as data: epistemica.results and report --csv/--parquet."""

from __future__ import annotations

import json
import sqlite3
import zlib

import pytest

pandas = pytest.importorskip("pandas")  # in the test extra

from epistemica.cli import main  # noqa: E402
from epistemica.del_.errors import InvalidArgumentError  # noqa: E402
from epistemica.results import STEP_COLUMNS, load, load_steps  # noqa: E402


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    path = tmp_path_factory.mktemp("data") / "r.sqlite"
    argv = [
        "sweep",
        "--robots",
        "2,3",
        "--trials",
        "2",
        "--reasoning",
        "rules-third,zero,convention",
    ]
    assert main([*argv, "--out", str(path)]) == 0
    return path


def test_load_is_the_trials_table(results):
    frame = load(results)
    db = sqlite3.connect(results)
    rows = db.execute("SELECT id, reasoning, robots, seed, success, steps FROM trials").fetchall()
    assert len(frame) == len(rows) == 12
    got = {
        (r.id, r.reasoning, r.robots, r.seed, bool(r.success), r.steps) for r in frame.itertuples()
    }
    assert got == {(i, lv, n, s, bool(ok), st) for i, lv, n, s, ok, st in rows}
    assert frame["success"].dtype == bool and "trace" not in frame.columns


def test_load_steps_is_every_trace_step_by_step(results):
    steps = load_steps(results)
    assert tuple(steps.columns) == STEP_COLUMNS
    db = sqlite3.connect(results)
    for trial_id, blob in db.execute("SELECT id, trace FROM trials"):
        trace = json.loads(zlib.decompress(blob).decode().replace("null", "NaN"))
        mine = steps[steps["id"] == trial_id]
        assert len(mine) == trace["steps"] * len(trace["robots"])
        last = mine[mine["step"] == trace["steps"] - 1]
        xs = [p[0] for p in trace["poses"][-1]]
        assert last["x"].tolist() == pytest.approx(xs)
        assert last["considered"].tolist() == trace["considered"][-1]


def test_load_steps_selects_trials_and_counts_rows_before_reading(results):
    trials = load(results)
    two = trials["id"].tolist()[:2]
    steps = load_steps(results, ids=two)
    assert sorted(set(steps["id"])) == sorted(two)
    expected = int(
        (trials.set_index("id").loc[two, "steps"] * trials.set_index("id").loc[two, "robots"]).sum()
    )
    assert len(steps) == expected
    assert len(load_steps(results, max_rows=expected, ids=two)) == expected
    with pytest.raises(
        InvalidArgumentError,
        match=f"hold {expected:,} step rows, more than max_rows={expected - 1:,}",
    ):
        load_steps(results, ids=two, max_rows=expected - 1)
    for bad in (0, -3, 2.5, True, "10"):
        with pytest.raises(InvalidArgumentError, match="max_rows must be a positive integer"):
            load_steps(results, max_rows=bad)


def test_report_writes_csv_and_parquet_and_lists_levels_in_study_order(results, tmp_path, capsys):
    csv = tmp_path / "trials.csv"
    assert main(["report", str(results), "--no-png", "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert f"trials: {csv}" in out
    table = [line.split()[1:4] for line in out.splitlines() if line.startswith("rendezvous")]
    levels = ["zero", "convention", "rules-third"]
    assert table == [[n, n, level] for n in ("2", "3") for level in levels]
    read = pandas.read_csv(csv)
    assert sorted(read["id"]) == sorted(load(results)["id"])
    pytest.importorskip("pyarrow")
    parquet = tmp_path / "trials.parquet"
    assert main(["report", str(results), "--no-png", "--parquet", str(parquet)]) == 0
    assert pandas.read_parquet(parquet).equals(load(results))


def test_report_never_writes_over_its_input(results, capsys):
    before = results.read_bytes()
    assert main(["report", str(results), "--no-png", "--csv", str(results)]) == 2
    assert "that is the command's input" in capsys.readouterr().err
    assert results.read_bytes() == before
