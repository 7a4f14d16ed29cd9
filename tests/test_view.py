"""``epistemica view`` and ``show --html``: self-contained pages with the right data.

What a browser does with the pages is tested in test_view_browser.py; here, without a
browser: the page's size, that it fetches nothing, that the embedded data is the trial's
or model's, and the command's inputs and errors.
"""

from __future__ import annotations

import json
import re
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from epistemica.cli import main
from epistemica.del_ import evaluate, load_spec
from epistemica.model_json import world_names
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.trace import encode, trial_trace
from epistemica.view import trial_page

SPECS = Path(__file__).resolve().parents[1] / "specs"


def _data(html: str):
    """The JSON embedded in a page, read back as a browser would."""
    text = re.search(r'<script id="data" type="application/json">(.*?)</script>', html, re.S)
    return json.loads(text.group(1).replace("<\\/", "</"))


@pytest.fixture(scope="module")
def long_trace():
    """A 100-step trial of 5 robots with limited sensing (the size target's case)."""
    for seed in range(20):
        s = Scenario.paper("rendezvous", 5, seed=seed, max_steps=100, sensing_range=8.0)
        trial = simulate(s, "zero", seed=seed)
        if trial.steps == 100:
            return trial_trace(s, trial)
    pytest.fail("no 100-step trial in 20 seeds")


def test_page_of_a_100_step_5_robot_trial_is_small_and_self_contained(long_trace):
    html = trial_page(long_trace, "rendezvous")
    assert len(html.encode()) < 2_000_000
    # Nothing is fetched: no external script, style, image, font or frame.
    for pattern in (r"<link", r"\ssrc=", r"@import", r"url\(", r"fetch\(", r"XMLHttpRequest"):
        assert not re.search(pattern, html), pattern
    data = _data(html)
    assert data["trials"][0]["trace"] == json.loads(json.dumps(long_trace).replace("NaN", "null"))
    assert (
        data["trials"][0]["trace"]["steps"] == 100
        and len(data["trials"][0]["trace"]["robots"]) == 5
    )


def test_names_cannot_close_the_data_script(long_trace):
    trace = {**long_trace, "policies": ["</script><b>x"] * 5}
    html = trial_page(trace)
    assert html.count("</script>") == 2  # the data element's and the program's
    assert _data(html)["trials"][0]["trace"]["policies"][0] == "</script><b>x"


def test_view_reads_a_trace_in_json_or_compressed(tmp_path, long_trace, capsys):
    (tmp_path / "t.json").write_text(json.dumps(long_trace))
    (tmp_path / "t.trace").write_bytes(encode(long_trace))
    for name in ("t.json", "t.trace"):
        out = tmp_path / f"{name}.html"
        assert main(["view", str(tmp_path / name), "-o", str(out)]) == 0
        assert _data(out.read_text())["trials"][0]["trace"]["poses"] == long_trace["poses"]
    assert "kB" in capsys.readouterr().out


def test_view_simulates_a_mission_files_trial(tmp_path):
    spec = SPECS / "nested" / "relocated_3.epi"
    out = tmp_path / "m.html"
    assert main(["view", str(spec), "--trial", "2", "--level", "rules-first", "-o", str(out)]) == 0
    trace = _data(out.read_text())["trials"][0]["trace"]
    assert trace["seed"] == 2 and set(trace["policies"]) == {"rules-first"}
    assert trace["robots"] == ["r1", "r2", "r3"] and trace["goals"][-1] == "g5"


def test_view_reads_traces_stored_in_a_results_file(tmp_path, long_trace):
    db = tmp_path / "r.sqlite"
    with sqlite3.connect(db) as con:
        con.execute("CREATE TABLE trials (id TEXT, mission TEXT, seed INT, reasoning TEXT)")
        con.execute("INSERT INTO trials VALUES ('a', 'rendezvous', 0, 'zero')")
    bare = subprocess.run(
        [sys.executable, "-m", "epistemica", "view", str(db), "-o", str(tmp_path / "x.html")],
        capture_output=True,
        text=True,
    )
    assert bare.returncode == 2 and "stores no traces" in bare.stderr
    assert "Traceback" not in bare.stderr
    with sqlite3.connect(db) as con:
        con.execute("ALTER TABLE trials ADD COLUMN trace BLOB")
        other = {**long_trace, "seed": 7}
        con.execute("UPDATE trials SET trace = ?", (encode(long_trace),))
        con.execute("INSERT INTO trials VALUES ('b', 'rendezvous', 7, 'zero', ?)", (encode(other),))
    out = tmp_path / "r.html"
    assert main(["view", str(db), "--trial", "7", "-o", str(out)]) == 0
    assert _data(out.read_text())["trials"][0]["trace"]["seed"] == 7
    assert main(["view", str(db), "--trial", "3", "-o", str(out)]) == 2


@pytest.mark.parametrize(
    "argv",
    [
        ["view", "specs/rendezvous.epi", "-o", "/no/such/dir/x.html"],
        ["view", "/no/such/file.json"],
        ["show", "specs/puzzles/muddy_children.epi", "--html", "/no/such/dir/m.html"],
        ["show", "specs/puzzles/muddy_children.epi", "--backend", "symbolic", "--html", "m.html"],
    ],
)
def test_bad_input_exits_2_with_a_hint(argv, tmp_path, monkeypatch, capsys):
    # In this process (main, what the script calls): the exit status of `python -m
    # epistemica view` is test_view_reads_traces_stored_in_a_results_file's.
    root = Path(__file__).resolve().parents[1]
    argv = [str(root / a) if a.startswith("specs/") else a for a in argv]
    monkeypatch.chdir(tmp_path)
    status = main(argv)
    err = capsys.readouterr().err
    assert status == 2, err
    assert "hint:" in err and "Traceback" not in err


def test_model_page_carries_the_model_and_the_claims_truth_sets(tmp_path):
    path = SPECS / "puzzles" / "muddy_children.epi"
    out = tmp_path / "m.html"
    assert main(["show", str(path), "--after", "father", "--html", str(out)]) == 0
    data = _data(out.read_text())
    spec = load_spec(str(path))
    model = spec.model.update(spec.actions["father"])
    names = world_names(model)
    ordered = [names[w] for w in model.worlds]
    assert [w["name"] for w in data["model"]["worlds"]] == ordered
    assert data["model"]["agents"] == ["c1", "c2", "c3"]
    assert len(data["claims"]) == len(spec.checks) > 0
    for claim, check in zip(data["claims"], spec.checks, strict=True):
        truth = evaluate(model, check.formula, spec.actions)
        assert claim["worlds"] == [n for n, t in zip(ordered, truth.tolist(), strict=True) if t]
        assert claim["holds"] == bool(truth[model.designated_positions].all())


@pytest.fixture(scope="module")
def joint_trace():
    """A short collaborative trial's trace."""
    from epistemica.mission import load_mission

    mission = load_mission(str(SPECS / "collaborative" / "tasks_3.epi"))
    scenario = mission.scenario(1).replace(max_steps=30)
    return trial_trace(scenario, simulate(scenario, "rules", seed=1))


def test_a_joint_trace_of_version_2_views_with_its_tasks_known(tmp_path, joint_trace):
    old = {k: v for k, v in joint_trace.items() if k != "tasks_known"}
    old.update(version=2, knows=joint_trace["tasks_known"])
    (tmp_path / "old.json").write_text(json.dumps(old))
    out = tmp_path / "old.html"
    assert main(["view", str(tmp_path / "old.json"), "-o", str(out)]) == 0
    trial = _data(out.read_text())["trials"][0]
    assert trial["trace"]["tasks_known"] == joint_trace["tasks_known"]
    assert "knows" not in trial["trace"] and trial["panels"][-1] == "events"
    since = joint_trace["aware_since"]  # how each robot learned each task it knew of
    mine = [[i, t, since[i][i][t]] for i in range(3) for t in range(3) if since[i][i][t] >= 0]
    assert sorted([i, t, step] for step, i, t, _ in trial["learned"]) == mine


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"kind": "relay"}, "a trace of an unknown kind 'relay'"),
        ({"steer_to": None}, "the trace's 'steer_to' is None, not a JSON list"),
        ({"aware_since": [[[0]]]}, "the trace's 'aware_since' is not an array of shape (3, 3, 3)"),
        ({"steer_to": [[0, 1]]}, "the trace's 'steer_to' is not an array of shape ("),
        ({"poses": [[[0, 0, 0]], "x"]}, "the trace's 'poses' is not an array of shape ("),
        ({"events": [[0, "found", ["r1"]]]}, "the trace is incomplete"),
    ],
)
def test_a_bad_joint_trace_exits_2_with_a_hint(
    tmp_path, joint_trace, change, message, monkeypatch, capsys
):
    (tmp_path / "bad.json").write_text(json.dumps({**joint_trace, **change}))
    monkeypatch.chdir(tmp_path)
    status = main(["view", str(tmp_path / "bad.json")])  # in this process, as above
    err = capsys.readouterr().err
    assert status == 2 and message in err and "hint:" in err
    assert "Traceback" not in err


def test_levels_are_compared_within_one_kind(joint_trace, long_trace):
    from epistemica.del_.errors import InvalidArgumentError

    with pytest.raises(InvalidArgumentError, match="different kinds of mission"):
        trial_page(long_trace, "", [joint_trace])
