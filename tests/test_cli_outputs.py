"""Every command that writes a file: never over its own input, never over a file unasked,
never through a dangling link, and a missing folder is created (issue 38, item 1)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from epistemica.cli import main
from epistemica.output_files import check_output, write_output

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "specs" / "puzzles" / "muddy_children.epi"


@pytest.fixture
def spec(tmp_path) -> Path:
    copy = tmp_path / "muddy.epi"
    copy.write_bytes(SPEC.read_bytes())
    return copy


def _refused(argv, capsys) -> str:
    assert main([str(a) for a in argv]) == 2
    return capsys.readouterr().err


def test_show_html_over_its_own_spec_is_refused_even_with_force(spec, capsys):
    before = spec.read_bytes()
    err = _refused(["show", spec, "--html", spec, "--force"], capsys)
    assert "input" in err and "Traceback" not in err
    assert spec.read_bytes() == before


def test_an_input_reached_by_another_path_or_a_link_is_still_the_input(spec, capsys):
    link = spec.parent / "link.html"
    link.symlink_to(spec)
    before = spec.read_bytes()
    _refused(["show", spec, "--dot", link, "--force"], capsys)
    _refused(["show", spec, "--dot", spec.parent / "." / spec.name, "--force"], capsys)
    assert spec.read_bytes() == before


def test_view_over_its_mission_file_is_refused(tmp_path, capsys):
    mission = tmp_path / "m.epi"
    mission.write_bytes((ROOT / "specs" / "rendezvous.epi").read_bytes())
    before = mission.read_bytes()
    _refused(["view", mission, "-o", mission, "--force"], capsys)
    assert mission.read_bytes() == before


def test_report_figure_over_its_results_file_is_refused(tmp_path, capsys):
    results = tmp_path / "r.sqlite"
    results.write_bytes(b"whatever the results file holds")
    for flag in ("--png", "--svg", "--pdf"):
        _refused(["report", results, flag, results, "--force"], capsys)
    assert results.read_bytes() == b"whatever the results file holds"


def test_an_existing_output_needs_force(spec, tmp_path, capsys):
    out = tmp_path / "muddy.dot"
    out.write_text("mine")
    err = _refused(["show", spec, "--dot", out], capsys)
    assert "--force" in err
    assert out.read_text() == "mine"
    assert main(["show", str(spec), "--dot", str(out), "--force"]) == 0
    assert out.read_text().startswith("digraph")


def test_export_refuses_existing_files_unless_forced(spec, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["export", "--smcdel", str(spec), "-o", str(out)]) == 0
    written = out / "muddy.smcdel"
    written.write_text("edited by hand")
    _refused(["export", "--smcdel", spec, "-o", out], capsys)
    assert written.read_text() == "edited by hand"
    assert main(["export", "--smcdel", str(spec), "-o", str(out), "--force"]) == 0
    assert "VARS" in written.read_text()


def test_a_dangling_link_is_never_written_through(spec, tmp_path, capsys):
    target = tmp_path / "elsewhere" / "created.html"
    link = tmp_path / "page.html"
    link.symlink_to(target)
    for force in ([], ["--force"]):
        err = _refused(["show", spec, "--html", link, *force], capsys)
        assert "dangling" in err
    assert not target.exists() and not target.parent.exists()


def test_force_replaces_a_link_itself_not_its_target(tmp_path):
    target = tmp_path / "kept.txt"
    target.write_text("kept")
    link = tmp_path / "out.txt"
    link.symlink_to(target)
    write_output(check_output(link, force=True), "new")
    assert not link.is_symlink() and link.read_text() == "new"
    assert target.read_text() == "kept"


def test_a_missing_folder_is_named_and_not_created(spec, tmp_path, capsys):
    out = tmp_path / "a" / "b" / "muddy.html"
    err = _refused(["show", spec, "--html", out], capsys)
    assert f"the folder {out.parent} does not exist" in err
    assert not (tmp_path / "a").exists()


def test_export_creates_its_output_folder(spec, tmp_path):
    out = tmp_path / "a" / "b"
    assert main(["export", "--epddl", str(spec), "-o", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == [
        "muddy-domain.epddl",
        "muddy-library.epddl",
        "muddy-problem.epddl",
    ]


def test_a_device_is_written_to_directly(spec):
    assert main(["show", str(spec), "--dot", os.devnull]) == 0  # no --force, no rename
    assert Path(os.devnull).exists() and not Path(os.devnull).is_file()


def test_a_folder_that_cannot_be_created_is_named(spec, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("")
    err = _refused(["export", "--smcdel", spec, "-o", blocker / "sub"], capsys)
    assert "cannot create the folder" in err and str(blocker) in err


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    out = tmp_path / "figure.png"
    out.write_bytes(b"old")

    def fails(path: Path) -> None:
        path.write_bytes(b"half")
        raise OSError(28, "No space left on device")

    with pytest.raises(Exception, match="No space left"):
        write_output(out, fails)
    assert out.read_bytes() == b"old"
    assert sorted(os.listdir(tmp_path)) == ["figure.png"]


def test_the_temporary_file_keeps_the_suffix_for_writers_that_read_it(tmp_path):
    seen = []
    write_output(tmp_path / "x.svg", lambda path: seen.append(path.suffix) or path.write_text(""))
    assert seen == [".svg"]
    mask = os.umask(0o022)
    os.umask(mask)
    assert os.stat(tmp_path / "x.svg").st_mode & 0o777 == 0o666 & ~mask  # not mkstemp's 0600
