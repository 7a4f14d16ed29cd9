"""``epistemica check``: claims, single formulas, JSON, exit codes and error reports."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from epistemica.cli import main

ROOT = Path(__file__).resolve().parents[1]
MUDDY = str(ROOT / "specs" / "puzzles" / "muddy_children.epi")


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def spec_file(tmp_path):
    def write(text: str, name: str = "t.epi") -> str:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return str(path)

    return write


def test_all_claims_of_the_muddy_children_hold(capsys):
    code, out, err = run(capsys, "check", MUDDY)
    assert code == 0 and err == ""
    assert "10 passed, 0 failed" in out
    assert "FAIL" not in out


def test_a_failing_claim_exits_1_and_is_reported_with_its_location(capsys, spec_file):
    path = spec_file('agents a\natoms p\nactual {p}\ncheck "good": p\ncheck "wrong": K[a] p\n')
    code, out, _ = run(capsys, "check", path)
    assert code == 1
    assert "1 passed, 1 failed" in out
    assert "FAIL" in out and "wrong" in out and f"{path}:5:1: K[a] p" in out


def test_expect_false_claims_pass_when_false(capsys, spec_file):
    path = spec_file('agents a\natoms p\nactual {p}\ncheck "not known": K[a] p expect false\n')
    code, out, _ = run(capsys, "check", path)
    assert code == 0 and "1 passed, 0 failed" in out


def test_formula_that_holds_exits_0_and_lists_the_worlds(capsys):
    # After the father, exactly the 7 worlds with at least one muddy child remain, and
    # "at least one is muddy" is common knowledge at all 8 worlds of the initial model
    # (at the clean world the announcement cannot be made, so the box is vacuous).
    code, out, _ = run(capsys, "check", MUDDY, "--formula", "[father] C[c1, c2, c3] (m1|m2|m3)")
    assert code == 0
    assert "true at the designated world" in out and "{m1, m2, m3}" in out
    assert "holds at 8 of 8 worlds" in out


def test_a_false_formula_is_answered_and_exits_1_only_when_expected_true(capsys):
    # With all three muddy, after the father and one round nobody knows yet.
    formula = "[!m1 | m2 | m3] [!~Kw[c1] m1 & ~Kw[c2] m2 & ~Kw[c3] m3] (K[c1] m1 & K[c2] m2)"
    code, out, _ = run(capsys, "check", MUDDY, "--formula", formula)
    assert code == 0  # a question, answered
    assert "false at the designated world" in out
    code, out, _ = run(capsys, "check", MUDDY, "--formula", formula, "--expect", "true")
    assert code == 1
    assert "false at the designated world" in out


def test_formula_json(capsys):
    code, out, _ = run(capsys, "check", MUDDY, "--formula", "K[c1] m2", "--json")
    data = json.loads(out)
    assert code == 0 and data["holds"] is True
    # c1 sees m2: K[c1] m2 holds exactly at the 4 worlds where m2 is true.
    assert data["n_worlds"] == 8 and data["n_true"] == 4
    assert all("m2" in w["atoms"] for w in data["worlds"])
    assert data["designated"] == [{"world": "w7", "atoms": ["m1", "m2", "m3"], "holds": True}]


def test_claims_json(capsys, spec_file):
    path = spec_file('agents a\natoms p\nactual {p}\ncheck "one": p\ncheck "two": ~p\n')
    code, out, _ = run(capsys, "check", path, "--json")
    data = json.loads(out)
    assert code == 1
    assert (data["passed"], data["failed"]) == (1, 1)
    assert [(c["name"], c["holds"], c["ok"], c["line"]) for c in data["claims"]] == [
        ("one", True, True, 4),
        ("two", False, False, 5),
    ]


@pytest.mark.parametrize(
    ("text", "formula", "where"),
    [
        ("agents a\natoms p\ngoal K[b] p\n", None, ":3:8: error: unknown agent 'b'"),
        ("agents a\natoms p\nlaw p &\n", None, ":3:8: error: expected a formula"),
        ("agents a\natoms p\n", "K[a] (p", "<formula>:1:8: error: expected ')'"),
        ("agents a\natoms p\n", "K[a] q", "<formula>:1:6: error: unknown atom 'q'"),
    ],
)
def test_bad_input_exits_2_with_location_and_hint(capsys, spec_file, text, formula, where):
    argv = ["check", spec_file(text)] + ([] if formula is None else ["--formula", formula])
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    assert where in err
    assert "\nhint: " in err and "Traceback" not in err
    assert "^" in err  # the caret under the offending column


def test_missing_file_exits_2(capsys, tmp_path):
    code, _, err = run(capsys, "check", str(tmp_path / "missing.epi"))
    assert code == 2 and "cannot read the spec file" in err and "hint:" in err


def test_usage_errors_exit_2(capsys):
    with pytest.raises(SystemExit) as info:
        main(["check"])
    assert info.value.code == 2
    assert "hint:" in capsys.readouterr().err
    with pytest.raises(SystemExit) as info:
        main(["frobnicate"])
    assert info.value.code == 2


def test_help_lists_commands_with_examples(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--help"])
    out = capsys.readouterr().out
    assert info.value.code == 0
    assert "check" in out and "plan" in out and "examples:" in out
    assert "epistemica check specs/puzzles/muddy_children.epi" in out


def test_no_command_prints_help_and_exits_2(capsys):
    code, out, _ = run(capsys)
    assert code == 2 and "usage:" in out


def test_python_dash_m_runs_the_main_job():
    result = subprocess.run(
        [sys.executable, "-m", "epistemica", "check", MUDDY],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=ROOT,
    )
    assert result.returncode == 0, result.stderr
    assert "10 passed, 0 failed" in result.stdout
    bad = subprocess.run(
        [sys.executable, "-m", "epistemica", "check", MUDDY, "--formula", "K[c9] m1"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert bad.returncode == 2
    assert "<formula>:1:3: error: unknown agent 'c9'" in bad.stderr
    assert "Traceback" not in bad.stderr
