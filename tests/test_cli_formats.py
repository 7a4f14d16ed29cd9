"""The command line on EPDDL and SMCDEL inputs, and ``epistemica export``: outputs, exit
statuses (0, 1, 2) and located errors, never a traceback."""

from __future__ import annotations

import json
from pathlib import Path

from epistemica.cli import main
from epistemica.del_.formats.epddl import load_epddl
from epistemica.del_.formats.smcdel import load_smcdel

DATA = Path(__file__).resolve().parent / "data" / "epddl"
TASK = [str(DATA / "peek.epddl"), str(DATA / "peek-1.epddl"), "-l", str(DATA / "library.epddl")]
SPECS = Path(__file__).resolve().parents[1] / "specs"


def test_plan_prints_the_plan_and_plank_s_form(capsys):
    assert main(["plan", *TASK]) == 0
    out = capsys.readouterr().out
    assert "1. peek(a)\n  2. call(a, b)\n  3. peek(b)" in out
    assert "validated" in out and out.rstrip().endswith("-a peek_a call_a_b peek_b")


def test_plan_json_has_plank_s_names(capsys):
    assert main(["plan", *TASK, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["plan"] == ["peek(a)", "call(a, b)", "peek(b)"] and out["valid"]
    assert out["plank_plan"] == ["peek_a", "call_a_b", "peek_b"]


def test_verify_and_show_take_plank_s_names(capsys):
    assert main(["plan", *TASK, "--verify", "peek_a,call_a_b,peek_b"]) == 0
    assert main(["plan", *TASK, "--verify", "call_a_b peek_b"]) == 1
    capsys.readouterr()
    assert main(["show", *TASK, "--after", "peek_a", "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["after"] == ["peek(a)"]


def test_check_a_formula_on_an_epddl_task(capsys):
    assert main(["check", *TASK, "--formula", "B[a] looking(a) & ~B[a] heads"]) == 0
    assert main(["check", *TASK, "--formula", "B[a] heads", "--expect", "true"]) == 1


def test_epddl_errors_exit_2_located(capsys):
    broken = DATA / "peek-1.epddl"
    assert main(["plan", str(DATA / "peek.epddl"), str(broken)]) == 2  # library missing
    err = capsys.readouterr().err
    assert "peek.epddl:6:27:" in err and "'test-types' is not given" in err
    assert "Traceback" not in err and "hint:" in err
    assert main(["plan", str(DATA / "peek.epddl")]) == 2
    assert "give the domain and the problem" in capsys.readouterr().err


def test_export_epddl_reads_back_with_the_same_plan_length(tmp_path, capsys):
    spec_file = SPECS / "planning" / "coin_in_the_box_a.epi"
    assert main(["export", "--epddl", str(spec_file), "-o", str(tmp_path)]) == 0
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [f"coin_in_the_box_a-{p}.epddl" for p in ("domain", "library", "problem")]
    files = [tmp_path / f"coin_in_the_box_a-{p}.epddl" for p in ("domain", "problem", "library")]
    back = load_epddl(files[0], files[1], [files[2]])
    capsys.readouterr()
    assert main(["plan", str(files[0]), str(files[1]), "-l", str(files[2]), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["length"] == 2
    assert back.spec.goal is not None


def test_export_and_check_smcdel(tmp_path, capsys):
    spec_file = SPECS / "puzzles" / "muddy_children.epi"
    assert main(["export", "--smcdel", str(spec_file), "-o", str(tmp_path)]) == 0
    written = tmp_path / "muddy_children.smcdel"
    assert load_smcdel(written).spec.atoms == ("m1", "m2", "m3")
    capsys.readouterr()
    assert main(["check", str(written)]) == 0
    assert "10 passed, 0 failed" in capsys.readouterr().out


def test_smcdel_where_queries_and_failures(tmp_path, capsys):
    path = tmp_path / "two.smcdel"
    text = "VARS 1,2\nLAW Top\nOBS a: 1\n     b: 2\nVALID? a knows whether 2\n"
    path.write_text(text + "WHERE? a knows that 1\n")
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out
    assert "FAIL  false  VALID? #1" in out and "2 of 4 states: {p1}; {p1, p2}" in out


def test_export_refuses_what_the_format_cannot_say(tmp_path, capsys):
    spec_file = SPECS / "puzzles" / "coin_toss.epi"
    assert main(["export", "--smcdel", str(spec_file), "-o", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "coin_toss.epi:" in err and "not a public announcement" in err


def test_export_of_a_plausibility_spec_is_refused_not_silently_lossy(tmp_path, capsys):
    spec = Path(__file__).resolve().parents[1] / "specs" / "belief" / "mary_and_john.epi"
    assert main(["export", "--epddl", str(spec), "-o", str(tmp_path)]) == 2
    assert "plausibility" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())
