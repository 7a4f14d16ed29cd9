"""A joint (collaborative) trial's trace: its own key for the tasks each robot knew of
(``tasks_known``, version 3), version-2 traces that called it ``knows`` still read (alone,
from a results file, as steps), and how each robot learned of each task."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import numpy as np
import pytest

from epistemica.cli import main
from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.study.store import read_rows, read_trace
from epistemica.sim.study.trace import (
    VERSION,
    decode,
    encode,
    known_goals,
    task_learning,
    trial_trace,
    upgraded,
)

SPEC = str(Path(__file__).resolve().parents[2] / "specs/collaborative/tasks_3.epi")


def _trace(seed: int = 1, level: str = "rules", steps: int = 60):
    scenario = load_mission(SPEC).scenario(seed).replace(max_steps=steps)
    trial = simulate(scenario, level, seed)
    return scenario, trial, trial_trace(scenario, trial)


def _as_version_2(trace: dict) -> dict:
    """The document the code before version 3 wrote for the same trial."""
    old = {k: v for k, v in trace.items() if k != "tasks_known"}
    return {**old, "version": 2, "knows": trace["tasks_known"]}


def test_the_joint_trace_keeps_what_each_robot_knew_under_its_own_key():
    _, trial, trace = _trace()
    assert trace["version"] == VERSION == 3 and trace["kind"] == "collaborative"
    assert "knows" not in trace  # the goal traces' change list keeps that name
    assert np.array_equal(np.array(trace["tasks_known"], dtype=bool), trial.knows)
    assert decode(encode(trace)) == trace


def test_a_version_2_joint_trace_reads_with_the_new_key():
    trace = _trace()[2]
    old = _as_version_2(trace)
    back = decode(encode(old))
    assert "knows" not in back and back["tasks_known"] == trace["tasks_known"]
    assert back["version"] == 2 and back["poses"] == trace["poses"]
    # a goal trace's `knows` is left alone, a v3 joint trace too (the same object)
    goal = {"version": 2, "knows": [[0, 0, 0, 0, 1, "start"]], "steps": 1, "robots": ["a"],
            "goals": ["g"]}  # fmt: skip
    assert upgraded(goal) is goal and known_goals(upgraded(goal))[0, 0, 0, 0]
    assert upgraded(trace) is trace


@pytest.fixture(scope="module")
def version_2_results(tmp_path_factory):
    """A results file of two collaborative trials whose traces are rewritten as the code
    before version 3 stored them."""
    folder = tmp_path_factory.mktemp("joint")
    text = Path(SPEC).read_text().replace("steps 400", "steps 40")
    (folder / "small.epi").write_text(text)
    out = folder / "small.sqlite"
    argv = ["run", str(folder / "small.epi"), "--trials", "1", "--levels", "rules-first,rules"]
    assert main([*argv, "--out", str(out), "--no-gif"]) == 0
    with sqlite3.connect(out) as db:
        for trial_id, blob in db.execute("SELECT id, trace FROM trials").fetchall():
            old = encode(_as_version_2(decode(blob)))
            db.execute("UPDATE trials SET trace = ? WHERE id = ?", (old, trial_id))
    return out


def test_a_results_file_with_version_2_joint_traces_loads(version_2_results):
    pandas = pytest.importorskip("pandas")
    from epistemica.results import load_steps

    rows = read_rows(version_2_results)
    traces = {r["id"]: read_trace(version_2_results, r["id"]) for r in rows}
    assert all(t["version"] == 2 and "tasks_known" in t for t in traces.values())
    steps = load_steps(version_2_results)
    assert isinstance(steps, pandas.DataFrame) and len(steps) == sum(
        t["steps"] * len(t["robots"]) for t in traces.values()
    )
    # the tasks each robot knew of at each step, counted from the stored array
    for trial_id, trace in traces.items():
        mine = steps[steps["id"] == trial_id].sort_values(["step", "robot"])
        expected = np.array(trace["tasks_known"]).sum(axis=2).ravel()
        assert mine["known_goals"].tolist() == expected.tolist()


def test_how_each_robot_learned_each_task_follows_the_trial():
    s, trial, trace = _trace(seed=0, steps=150)
    learned = task_learning(trace)
    mine = np.einsum("iit->it", trial.aware_since)
    assert sorted((i, t) for _, i, t, _ in learned) == sorted(map(tuple, np.argwhere(mine >= 0)))
    for step, i, t, how in learned:
        assert step == mine[i, t]
        task = s.task_names[t]  # a joint trial's event: (step, name, arguments, observers)
        named = [e for e in trial.events if e[0] == step and i in e[3] and task in map(str, e[2])]
        near = np.hypot(*(trial.trajectory[step, i, :2] - s.tasks[t])) <= s.sensing_range
        assert how == (named[0][1] if named else "seen" if near else "told")
    assert {how for *_, how in learned} - {"seen", "told"}  # events taught some of them
