"""Every documented ``epistemica`` command runs as written: each bash line of README.md and
docs/*.md that tests/test_docs_examples.py parses is run here, in the order of its page, in
a fresh folder per page (where ``specs/`` and ``tests/`` lead to the repository's), and
must exit 0 and write the files it names.

What the test changes, and why (nothing else is changed):

- the budget: ``run`` and ``sweep`` take ``--trials 1`` (instead of the file's or the
  written number; ``--paper-scale``, 50 trials per level, is dropped for it), so that every
  page's commands run in seconds rather than hours, and ``--workers 1`` (in this process: a
  pool of every core would start its processes for a handful of trials, on a machine the
  suite shares); the command line is otherwise as written;
- animations: at most 3 frames each (the ``few_frames`` fixture of tests/conftest.py),
  drawn and written by the real code, where a GIF of 60 frames took most of a page's time;
- placeholders for a user's files: ``my_mission.epi`` (a mission of the reader's whose
  robots are ``r1..rN``) is :data:`MY_MISSION`;
- an output that needs an optional extra the test environment lacks (``--parquet``:
  pyarrow, the ``data`` extra, not the ``test`` one) is left out of the command line, and
  the rest of it runs (:data:`OPTIONAL`).

Commands run in this process (``epistemica.cli.main``, what the ``epistemica`` script
calls), which saves a start-up per command.
"""

from __future__ import annotations

import importlib.util
import shlex
from pathlib import Path

import pytest
from test_cli_missions_swept import TEAM
from test_docs_examples import DOCS, ROOT, documented_commands

from epistemica.cli import main

pytest.importorskip("matplotlib")  # run, simulate --gif and report draw figures

#: The reader's own mission of the docs' ``sweep --mission my_mission.epi --robots 2..8``
#: (robots and goals as spans up to ``N``, docs/language.md "The team size as a
#: parameter"): the one the team-size tests use, two cheap levels.
MY_MISSION = TEAM

#: An output flag -> the module it needs (an optional extra's).
OPTIONAL = {"--parquet": "pyarrow"}

#: Flags whose value is a file (or, for ``export -o``, a folder) the command writes.
_WRITES = ("--gif", "--png", "--csv", "--parquet", "--html", "--dot")


def budgeted(argv: list[str]) -> list[str]:
    """``argv`` at the test's budget: ``run`` and ``sweep`` with one trial per cell, in this
    process; without the outputs whose optional library is missing."""
    out = list(argv)
    for flag, module in OPTIONAL.items():
        if flag in out and importlib.util.find_spec(module) is None:
            k = out.index(flag)
            del out[k : k + 2]
    if out[0] not in ("run", "sweep"):
        return out
    out = [a for a in out if a != "--paper-scale"]
    if "--trials" in out:
        out[out.index("--trials") + 1] = "1"
    else:
        out += ["--trials", "1"]
    return [*out, "--workers", "1"]


def claimed_outputs(argv: list[str]) -> list[str]:
    """The files (a trailing ``/``: a folder with something in it) a command line says it
    writes, by the commands' documented defaults (``epistemica COMMAND --help``)."""
    command, out = argv[0], []
    for k, arg in enumerate(argv[:-1]):
        if arg in _WRITES or (arg == "--out" and command == "sweep"):
            out.append(argv[k + 1])
        if arg in ("-o", "--out") and command in ("view", "export"):
            out.append(argv[k + 1].rstrip("/") + ("/" if command == "export" else ""))
        if arg in ("--pdf", "--svg") and command == "report":
            out.append(argv[k + 1])
    if command == "run":
        files = [a for a in argv[1:] if a.endswith(".epi")]
        kinds = ["sqlite", "png", "html"] + ([] if "--no-gif" in argv else ["gif"])
        out += [f"runs/{Path(f).stem}.{kind}" for f in files for kind in kinds]
    figures = ("--png", "--pdf", "--svg", "--no-png")
    if command == "report" and not any(a in argv for a in figures):
        out.append(str(Path(argv[1]).with_suffix(".png")))
    return out


def test_the_budget_and_the_claimed_files_read_the_command_line_as_documented():
    run = ["run", "specs/rendezvous.epi", "--paper-scale"]
    assert budgeted(run) == ["run", "specs/rendezvous.epi", "--trials", "1", "--workers", "1"]
    assert budgeted(["sweep", "--trials", "50", "--out", "x"]) == [
        *("sweep", "--trials", "1", "--out", "x", "--workers", "1")
    ]
    assert budgeted(["check", "a.epi"]) == ["check", "a.epi"]
    assert claimed_outputs(["run", "a/b.epi", "--no-gif"]) == [
        *("runs/b.sqlite", "runs/b.png", "runs/b.html")
    ]
    assert claimed_outputs(["report", "runs/s.sqlite", "--markdown"]) == ["runs/s.png"]
    assert claimed_outputs(["report", "r.sqlite", "--no-png", "--csv", "t.csv"]) == ["t.csv"]
    assert claimed_outputs(["export", "--smcdel", "m.epi", "-o", "out/"]) == ["out/"]


def _workdir(tmp_path: Path) -> Path:
    for name in ("specs", "tests"):
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    (tmp_path / "my_mission.epi").write_text(MY_MISSION, encoding="utf-8")
    return tmp_path


PAGES = sorted({path for path, _, _ in documented_commands()})


def test_the_pages_with_commands_are_the_ones_expected():
    assert {p.name for p in PAGES} >= {"README.md", "language.md", "simulation.md", "epddl.md"}
    assert all(p in DOCS for p in PAGES)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_documented_command_runs_and_writes_what_it_says(
    page, tmp_path, monkeypatch, few_frames
):
    commands = [(line, command) for path, line, command in documented_commands() if path == page]
    monkeypatch.chdir(_workdir(tmp_path))
    failures = []
    for line, command in commands:
        argv = budgeted(shlex.split(command)[1:])
        status = main(argv)
        missing = [
            f
            for f in claimed_outputs(argv)
            if not (Path(f).is_file() or (f.endswith("/") and any(Path(f).iterdir())))
        ]
        if status != 0 or missing:
            failures.append(f"{page.name}:{line}: {command!r}: exit {status}, missing {missing}")
    assert not failures, "\n".join(failures)
