"""Reading input files on the command line: bounded, once, text only, the right language.

Every case is a one-line reproduction of a finding of issue 22, with the exit status and
the sentence a user must see.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from epistemica.cli import main
from epistemica.del_ import SourceError, load_spec
from epistemica.del_.spec import _source as source
from epistemica.del_.spec._source import MAX_CLAIMS, read_source
from epistemica.input_files import file_kind

ROOT = Path(__file__).resolve().parents[1]
MUDDY = ROOT / "specs" / "puzzles" / "muddy_children.epi"
MISSION = ROOT / "specs" / "rendezvous.epi"


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_devices_are_refused_at_once(capsys, device):
    start = time.perf_counter()
    code, _, err = run(capsys, "check", device)
    assert code == 2 and "is binary, not text" in err
    assert time.perf_counter() - start < 2  # one 64 kB block, not gigabytes


def test_a_file_over_the_size_limit_is_refused(tmp_path):
    path = tmp_path / "big.epi"
    path.write_text("agents a\n" + "# padding\n" * 2000, encoding="utf-8")
    with pytest.raises(SourceError, match="larger than the limit of 1,000 bytes"):
        read_source(path, limit=1000)


def test_a_byte_order_mark_is_accepted(capsys, tmp_path):
    path = tmp_path / "bom.epi"
    path.write_bytes(b"\xef\xbb\xbf" + MUDDY.read_bytes())
    code, out, _ = run(capsys, "check", path)
    assert code == 0 and "10 passed, 0 failed" in out


def test_an_encoding_error_says_what_and_where(capsys, tmp_path):
    path = tmp_path / "latin1.epi"
    path.write_bytes(b"agents a\natoms p\n# caf\xe9\n")
    code, _, err = run(capsys, "check", path)
    assert code == 2
    assert f"{path}:3:6: error:" in err and "not UTF-8" in err and "0xe9" in err
    assert "check the path" not in err


def test_a_missing_file_says_check_the_path(capsys, tmp_path):
    code, _, err = run(capsys, "check", tmp_path / "nope.epi")
    assert code == 2 and "No such file" in err and "check the path" in err


def test_a_pipe_is_read_once():
    """`check <(cat FILE)`: the file descriptor can be read only once."""
    read, write = os.pipe()
    os.write(write, MUDDY.read_bytes())
    os.close(write)
    out = subprocess.run(
        [sys.executable, "-m", "epistemica", "check", f"/dev/fd/{read}"],
        pass_fds=(read,), capture_output=True, text=True, check=False,
    )  # fmt: skip
    os.close(read)
    assert out.returncode == 0, out.stderr
    assert "10 passed, 0 failed" in out.stdout


def test_a_mission_given_to_a_spec_command_names_the_right_commands(capsys):
    for command in ("plan", "show"):
        code, _, err = run(capsys, command, MISSION)
        assert code == 2
        assert "this is a mission file" in err and "epistemica run" in err
        assert "expected" not in err  # not a grammar error about spec keywords


def test_a_spec_given_to_run_names_the_right_commands(capsys):
    code, _, err = run(capsys, "run", MUDDY, "--no-gif")
    assert code == 2
    assert "this is a spec file" in err and "epistemica check" in err


def test_a_file_starting_with_robot_gets_one_answer_from_check_and_run(capsys, tmp_path):
    path = tmp_path / "headless.epi"
    path.write_text("robot a: range at random\ngoal x at (3, 3)\n", encoding="utf-8")
    answers = []
    for argv in (("check", path), ("run", path, "--no-gif")):
        code, _, err = run(capsys, *argv)
        answers.append((code, err.strip()))
    assert answers[0] == answers[1]
    assert answers[0][0] == 2 and "its first statement is 'robot', not 'mission'" in answers[0][1]


@pytest.mark.parametrize(
    ("text", "kind"),
    [
        ("# comment\n\nmission rendezvous\n", "mission"),
        ("robot r1: range at random\n", "headless"),
        ("workspace 30\n", "headless"),
        ("agents a\n", "spec"),
        ("goal p\n", "spec"),  # goal and check exist in both languages: a spec
        ("", "spec"),
    ],
)
def test_the_first_statement_decides_the_language(text, kind):
    assert file_kind(text)[0] == kind


def test_undeclared_names_in_a_mission_formula_exit_2(capsys):
    code, _, err = run(capsys, "check", MISSION, "--formula", "assigned(r1, g9)")
    assert code == 2 and "unknown atom 'assigned(r1, g9)'" in err


def test_undeclared_names_in_a_spec_formula_exit_2(capsys):
    code, _, err = run(capsys, "check", MUDDY, "--formula", "K[c1] mud1")
    assert code == 2 and "unknown atom 'mud1'" in err


def test_load_spec_has_one_meaning_on_both_sides(tmp_path):
    """The API's load_spec is the CLI's: 'auto' is symbolic past 20 observed atoms."""
    path = tmp_path / "wide.epi"
    path.write_text("agents a\natoms m1..m21\nobserves a: m1\n", encoding="utf-8")
    assert type(load_spec(path).model).__name__ == "KnowledgeStructure"
    assert type(load_spec(path, backend="explicit").model).__name__ == "KripkeModel"
    assert type(load_spec(MUDDY).model).__name__ == "KripkeModel"
    assert type(load_spec(MUDDY, backend="symbolic").model).__name__ == "KnowledgeStructure"
    with pytest.raises(ValueError, match="unknown backend"):
        load_spec(MUDDY, backend="fast")


def test_more_than_twenty_atoms_without_actual_and_an_unobserved_atom(capsys, tmp_path):
    """Issue 22: n_worlds shifted by a negative count (exit 3). 21 atoms, a sees m1 only,
    m21 is observed by nobody, every world designated: 2^21 worlds, and a cannot know m2."""
    path = tmp_path / "wide.epi"
    path.write_text(
        'agents a\natoms m1..m21\nobserves a: m1\ncheck "a does not know m2": ~Kw[a] m2\n',
        encoding="utf-8",
    )
    code, out, _ = run(capsys, "check", path)
    assert code == 0 and "2,097,152 worlds" in out and "1 passed, 0 failed" in out


def test_too_many_claims_are_refused_before_parsing(capsys, tmp_path):
    path = tmp_path / "many.epi"
    claims = "".join(f'check "c{i}": p | ~p\n' for i in range(MAX_CLAIMS + 1))
    path.write_text("agents a\natoms p\n" + claims)
    code, _, err = run(capsys, "check", str(path))
    assert code == 2
    # The first claim too many is on line 2 + MAX_CLAIMS + 1, column 1.
    assert f"many.epi:{MAX_CLAIMS + 3}:1: error: more than {MAX_CLAIMS} claims" in err
    assert "Traceback" not in err
    path.write_text("agents a\natoms p\n" + claims.split("\n", 1)[1])  # exactly the limit
    assert len(load_spec(path).checks) == MAX_CLAIMS


def test_too_many_tokens_are_refused_before_parsing(capsys, tmp_path, monkeypatch):
    # tokens: agents a NL (3), atoms p NL (3), then law p NL (3 each)
    monkeypatch.setattr(source, "MAX_TOKENS", 6 + 3 * 4)
    path = tmp_path / "tokens.epi"
    path.write_text("agents a\natoms p\n" + "law p\n" * 4)
    code, out, _ = run(capsys, "check", path)
    assert code == 0 and "0 passed, 0 failed" in out
    path.write_text("agents a\natoms p\n" + "law p\n" * 4 + "law ~p\n")  # token 19: 'law'
    code, _, err = run(capsys, "check", path)
    assert code == 2 and "Traceback" not in err
    assert f"{path}:7:1: error: more than 18 tokens (words, symbols and line ends)" in err
    for argv in (["show", path], ["plan", path]):  # every command reads through parse_spec
        code, _, err = run(capsys, *argv)
        assert code == 2 and ":7:1: error: more than 18 tokens" in err
