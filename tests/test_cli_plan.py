"""``epistemica plan``: plans, explanations, JSON, exit codes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from epistemica.cli import main

MUDDY = str(Path(__file__).resolve().parents[1] / "specs" / "puzzles" / "muddy_children.epi")

# The only shortest plan: "nobody knows" before the father teaches nothing, and after the
# father the three muddy children need two rounds of "nobody knows" (published answer).
MUDDY_PLAN = ["father", "nobody_knows", "nobody_knows"]


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("search", ["bfs", "astar"])
def test_muddy_children_plan(capsys, search):
    code, out, err = run(capsys, "plan", MUDDY, "--search", search)
    assert code == 0, err
    steps = [line.split(". ", 1)[1] for line in out.splitlines() if line.startswith("  ")]
    assert steps == MUDDY_PLAN
    assert "validated" in out


def test_greedy_finds_a_valid_plan(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--search", "greedy", "--json")
    data = json.loads(out)
    assert code == 0 and data["valid"] and data["plan"][-2:] == ["nobody_knows", "nobody_knows"]


def test_plan_json_and_explain(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--json", "--explain")
    data = json.loads(out)
    assert code == 0
    assert data["plan"] == MUDDY_PLAN and data["length"] == 3 and data["valid"] is True
    assert data["goal"] == "K[c1] m1 & K[c2] m2 & K[c3] m3"
    # One description per state: initial plus one per step. The muddy children's
    # surviving worlds (after contraction): 8, then 7 (>= 1 muddy), 4 (>= 2), 1.
    assert [s.split(" ", 1)[0] for s in data["states"]] == ["8", "7", "4", "1"]


def test_explain_text_marks_the_designated_world(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--explain")
    assert code == 0
    assert "initial state:" in out
    assert "* w7  {m1, m2, m3}" in out  # the actual world of the initial model
    assert "c1: {w0, w4}" in out  # c1 confuses the worlds that differ in m1 only


def test_depth_bound_too_small_exits_1(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--max-depth", "2")
    assert code == 1 and "no plan within the search bound" in out


def test_impossible_goal_exits_1(capsys, tmp_path):
    path = tmp_path / "never.epi"
    path.write_text("agents a\natoms p\nactual {}\naction tell: public p\ngoal K[a] p\n")
    code, out, _ = run(capsys, "plan", str(path))
    # p is false and nothing changes it, so no plan exists (the search space is finite).
    assert code == 1 and "no plan exists" in out


def test_spec_without_goal_exits_2(capsys, tmp_path):
    path = tmp_path / "nogoal.epi"
    path.write_text("agents a\natoms p\naction tell: public p\n")
    code, _, err = run(capsys, "plan", str(path))
    assert code == 2 and "no goal" in err and "hint:" in err and "Traceback" not in err


@pytest.mark.parametrize("depth", ["-1", "x", "1.5"])
def test_bad_max_depth_exits_2(capsys, depth):
    with pytest.raises(SystemExit) as info:
        main(["plan", MUDDY, "--max-depth", depth])
    assert info.value.code == 2
    assert "non-negative integer" in capsys.readouterr().err


def test_unknown_search_exits_2(capsys):
    with pytest.raises(SystemExit) as info:
        main(["plan", MUDDY, "--search", "dfs"])
    assert info.value.code == 2
