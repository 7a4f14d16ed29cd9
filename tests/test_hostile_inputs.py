"""Every reader refuses hostile input with exit 2 and one message: endless or random bytes,
decompression bombs, oversized files (issue 38, item 2), and the viewer page renders any
string and number a trace can hold (item 3).

benchmarks/hostile_inputs.py times the same cases through the installed command."""

from __future__ import annotations

import functools
import json
import math
import os
import sqlite3
import zlib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.cli import main
from epistemica.del_.errors import InvalidArgumentError
from epistemica.html_view import page
from epistemica.input_files import MAX_MISSION_BYTES
from epistemica.sim.study.trace import MAX_TRACE_BYTES, decode

ROOT = Path(__file__).resolve().parents[1]
MISSION = ROOT / "specs" / "rendezvous.epi"


def _link(tmp_path: Path, device: str, name: str) -> str:
    link = tmp_path / name
    link.symlink_to(device)
    return str(link)


def _exit_2(argv, capsys) -> str:
    assert main([str(a) for a in argv]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "internal error" not in err
    return err


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_endless_bytes_are_refused_by_every_reader(device, tmp_path, capsys):
    if not os.path.exists(device):
        pytest.skip(f"no {device}")
    smcdel, epddl = _link(tmp_path, device, "x.smcdel"), _link(tmp_path, device, "d.epddl")
    policy = _link(tmp_path, device, "p.json")
    implicit = ROOT / "specs" / "planning" / "two_robots_implicit.epi"
    for argv in (
        ["check", device],
        ["view", device, "-o", tmp_path / "v.html"],
        ["run", device],
        ["check", smcdel],
        ["plan", epddl, epddl],
        ["plan", implicit, "--implicit", "--policy", "--verify", policy],
        ["report", device, "--no-png"],
    ):
        _exit_2(argv, capsys)


@functools.cache  # bytes, never changed: two tests, one compression of 1 GiB (3 s)
def _bomb() -> bytes:
    # zlib output of 1 GiB of spaces is about 1 MB: inflating it whole would cost 1 GiB.
    inflater = zlib.compressobj(9)
    chunk = b" " * (1 << 24)
    return b"".join([*(inflater.compress(chunk) for _ in range(64)), inflater.flush()])


def test_a_trace_bomb_is_refused_after_the_limit(tmp_path, capsys):
    bomb = _bomb()
    assert len(bomb) < (2 << 20) and MAX_TRACE_BYTES < (1 << 30)
    with pytest.raises(InvalidArgumentError, match="inflates beyond"):
        decode(bomb)
    path = tmp_path / "bomb.z"
    path.write_bytes(bomb)
    assert "inflates beyond" in _exit_2(["view", path, "-o", tmp_path / "b.html"], capsys)


def test_a_trace_bomb_stored_in_a_results_file_is_refused(tmp_path, capsys):
    db = tmp_path / "r.sqlite"
    with sqlite3.connect(db) as connection:
        connection.execute("CREATE TABLE trials (id TEXT, seed INT, reasoning TEXT, "
                           "mission TEXT, trace BLOB)")  # fmt: skip
        connection.execute("INSERT INTO trials VALUES ('a', 0, 'zero', 'm', ?)", (_bomb(),))
    assert "inflates beyond" in _exit_2(["view", db, "-o", tmp_path / "b.html"], capsys)


def test_a_results_file_with_non_json_options_is_bad_input(tmp_path, capsys):
    from epistemica.sim.study.store import ResultStore

    db = tmp_path / "r.sqlite"
    row = {"id": "1", "mission": "rendezvous", "robots": 2, "goals": 2, "reasoning": "zero",
           "seed": 0, "options": "{not json", "success": 1, "steps": 9,
           "completion_step": None, "wall_time": 0.1, "decision_ms": 0.1, "considered": 1.0,
           "version": "0"}  # fmt: skip
    with ResultStore(db) as store:
        store.add(row)
    assert "options" in _exit_2(["report", db, "--no-png"], capsys)


def test_a_deeply_nested_json_trace_is_bad_input(tmp_path, capsys):
    path = tmp_path / "deep.json"
    path.write_text('{"a":' * 100_000 + "1" + "}" * 100_000)
    _exit_2(["view", path, "-o", tmp_path / "d.html"], capsys)


def test_an_oversized_mission_is_refused_before_compiling(tmp_path, capsys):
    path = tmp_path / "big.epi"
    claim = 'check "x": K[r1] true\n'
    path.write_text(MISSION.read_text() + claim * (MAX_MISSION_BYTES // len(claim) + 1))
    for argv in (["check", path], ["run", path], ["view", path, "-o", tmp_path / "p.html"]):
        assert "larger than the limit" in _exit_2(argv, capsys)


def _embedded(html: str):
    """The data of a page as a browser's parser finds it: the text of the first
    ``<script type="application/json">`` element, up to the first ``</script``."""
    start = html.index(">", html.index('type="application/json"')) + 1
    return json.loads(html[start : html.index("</script", start)])


@settings(max_examples=60, deadline=None)
@given(
    st.recursive(
        st.none() | st.booleans() | st.floats() | st.integers() | st.text(),
        lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(), inner, max_size=4),
        max_leaves=12,
    )
)
def test_the_page_data_survives_any_string_and_number(value):
    html = page("t", "trial_view.js", {"value": value})
    data = _embedded(html)["value"]
    assert data == _nulled(value)
    embedded = html[html.index('type="application/json"') :]
    embedded = embedded[: embedded.index("</script")]
    assert "<!--" not in embedded and "<script" not in embedded.lower()


def _nulled(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list):
        return [_nulled(v) for v in value]
    if isinstance(value, dict):
        return {k: _nulled(v) for k, v in value.items()}
    return value


def test_the_page_keeps_nan_inside_strings_and_hostile_markup_inert():
    data = {"robots": ["NaNo", "<!--<script>", "</script><script>alert(1)</script>"],
            "x": [float("inf"), float("-inf"), float("nan"), 1.5]}  # fmt: skip
    got = _embedded(page("t", "trial_view.js", data))
    assert got == {"robots": data["robots"], "x": [None, None, None, 1.5]}


def _results_file(path: Path, rows: int, options: str = "{}", trace: bytes | None = None) -> None:
    from epistemica.sim.study.store import ResultStore

    with ResultStore(path) as store:
        for i in range(rows):
            store.add({"id": f"t{i}", "mission": "rendezvous", "robots": 2, "goals": 2,
                       "reasoning": "zero", "seed": i, "options": options, "success": 1,
                       "steps": 9, "completion_step": 9, "wall_time": 0.1, "decision_ms": 0.1,
                       "considered": 1.0, "version": "0", "trace": trace})  # fmt: skip


def test_a_results_file_over_the_row_limit_is_refused_before_reading(tmp_path, capsys, monkeypatch):
    from epistemica.sim.study import store

    monkeypatch.setattr(store, "MAX_ROWS", 3)
    db = tmp_path / "r.sqlite"
    _results_file(db, 3)
    assert [r["seed"] for r in store.read_rows(db)] == [0, 1, 2]
    assert main(["report", str(db), "--no-png"]) == 0
    capsys.readouterr()
    more = tmp_path / "more.sqlite"
    _results_file(more, 4)
    assert "4 trials, more than the limit of 3" in _exit_2(["report", more, "--no-png"], capsys)


def test_a_results_file_with_an_oversized_value_is_refused(tmp_path, capsys):
    from epistemica.sim.study.store import MAX_CELL_BYTES, read_rows

    db, big = tmp_path / "r.sqlite", tmp_path / "big.sqlite"
    options = '{"x": "' + "a" * (MAX_CELL_BYTES - 9) + '"}'  # exactly MAX_CELL_BYTES
    _results_file(db, 1, options)
    assert len(read_rows(db)[0]["options"]) == MAX_CELL_BYTES
    _results_file(big, 1, options[:-2] + 'a"}')
    err = _exit_2(["report", big, "--no-png"], capsys)
    assert f"a value of {MAX_CELL_BYTES + 1:,} bytes, over the limit" in err


def _small_trace() -> dict:
    from epistemica.sim import Scenario, simulate
    from epistemica.sim.study.trace import trial_trace

    scenario = Scenario.paper("rendezvous", 2, 2, seed=0, max_steps=5)
    return trial_trace(scenario, simulate(scenario, "zero", seed=0))


def test_a_stored_trace_over_the_limit_is_not_fetched(tmp_path, capsys, monkeypatch):
    from epistemica.sim.study import trace as traces
    from epistemica.sim.study.store import read_trace

    blob = traces.encode(_small_trace())
    db = tmp_path / "r.sqlite"
    _results_file(db, 1, trace=blob)
    monkeypatch.setattr(traces, "MAX_TRACE_BYTES", len(blob) * 100)  # inflated it is larger
    assert read_trace(db, "t0")["seed"] == 0
    assert main(["view", str(db), "-o", str(tmp_path / "ok.html")]) == 0
    monkeypatch.setattr(traces, "MAX_TRACE_BYTES", len(blob) - 1)
    with pytest.raises(InvalidArgumentError, match=f"is {len(blob):,} bytes, over the limit"):
        read_trace(db, "t0")
    err = _exit_2(["view", db, "-o", tmp_path / "no.html"], capsys)
    assert f"the stored trace is {len(blob):,} bytes, over the limit of {len(blob) - 1:,}" in err


def test_a_trace_or_policy_file_over_16_mib_is_refused(tmp_path, capsys):
    path = tmp_path / "big.json"
    path.write_text('{"format": "' + " " * MAX_TRACE_BYTES + '"}')
    err = _exit_2(["view", path, "-o", tmp_path / "b.html"], capsys)
    assert f"larger than the limit of {MAX_TRACE_BYTES:,} bytes" in err
    implicit = ROOT / "specs" / "planning" / "two_robots_implicit.epi"
    argv = ["plan", implicit, "--implicit", "--policy", "--verify", path]
    assert f"larger than the limit of {MAX_TRACE_BYTES:,} bytes" in _exit_2(argv, capsys)


def test_a_deeply_nested_policy_is_bad_input(tmp_path, capsys):
    implicit = ROOT / "specs" / "planning" / "two_robots_implicit.epi"
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)  # json raises RecursionError, not ValueError
    argv = ["plan", implicit, "--implicit", "--policy", "--verify", path]
    assert "cannot read the policy" in _exit_2(argv, capsys)


def test_a_mission_over_the_token_limit_is_refused_before_parsing(tmp_path, capsys, monkeypatch):
    import epistemica.mission as missions

    # tokens by hand: mission rendezvous NL (3), workspace 30 NL (3),
    # robot r1 . . r2 : range at random NL (10), goal g1 . . g2 at random NL (8)
    text = "mission rendezvous\nworkspace 30\nrobot r1..r2: range at random\n"
    text += "goal g1..g2 at random\n"
    monkeypatch.setattr(missions, "MAX_MISSION_TOKENS", 24)
    assert missions.parse_mission(text).robots == ("r1", "r2")
    path = tmp_path / "m.epi"
    path.write_text(text + "# one word too many\n")  # token 25: '#' at 5:1
    err = _exit_2(["check", path], capsys)
    assert f"{path}:5:1: error: more than 24 tokens (words, symbols and line ends)" in err


def test_a_results_file_meta_table_is_read_only_where_needed(tmp_path, capsys):
    db = tmp_path / "r.sqlite"
    _results_file(db, 1)
    with sqlite3.connect(db) as connection:  # a long format tag, and many other entries
        connection.execute("UPDATE meta SET value = ? WHERE key = 'format'", ("x" * 10**6,))
        others = ((f"k{i}", "v") for i in range(1000))
        connection.executemany("INSERT INTO meta VALUES (?, ?)", others)
    err = _exit_2(["report", db, "--no-png"], capsys)
    assert f"format '{'x' * 64}')" in err  # the tag as read: its first 64 characters
