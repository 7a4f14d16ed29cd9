"""The exit-status contract of every command, ``--debug``, and a lean start-up.

0 success, 1 a false claim (or --expect) or no plan, 2 bad input, 3 an internal error (one
line saying it is a bug, where to report it and that ``--debug`` shows the traceback),
130 interrupted. No traceback without ``--debug``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from epistemica.cli import build_parser, main
from epistemica.cli import check as cli_check
from epistemica.cli import plan as cli_plan

ROOT = Path(__file__).resolve().parents[1]
MUDDY = str(ROOT / "specs" / "puzzles" / "muddy_children.epi")


def epistemica(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "epistemica", *argv],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )


@pytest.mark.parametrize(
    ("argv", "status"),
    [
        (["check", MUDDY], 0),
        (["check", MUDDY, "--formula", "[father] K[c1] m1"], 0),  # a question: answered
        (["check", MUDDY, "--formula", "[father] K[c1] m1", "--expect", "true"], 1),  # no
        (["check", MUDDY, "--formula", "K[c9] m1"], 2),  # no agent c9
        (["plan", MUDDY, "--max-depth", "1"], 1),  # three rounds are needed
        (["show", MUDDY, "--after", "father"], 0),
        (["show", MUDDY, "--after", "fathr"], 2),
        (["check", str(ROOT / "no" / "such.epi")], 2),
    ],
)
def test_real_commands_exit_with_the_contracted_status(argv, status):
    run = epistemica(*argv)
    assert run.returncode == status, run.stderr
    assert "Traceback" not in run.stderr


def boom(args):
    raise ZeroDivisionError("injected")


@pytest.mark.parametrize("module", [cli_check, cli_plan])
def test_an_internal_error_exits_3_with_one_line_and_no_traceback(capsys, monkeypatch, module):
    name = "run_check" if module is cli_check else "run_plan"
    monkeypatch.setattr(module, name, boom)
    code = main([name[4:], MUDDY])
    out, err = capsys.readouterr()
    assert code == 3 and out == ""
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert "ZeroDivisionError: injected" in err
    assert "bug in epistemica" in err and "issue tracker" in err and "--debug" in err


@pytest.mark.parametrize("where", ["before", "after"])
def test_debug_prints_the_traceback(capsys, monkeypatch, where):
    monkeypatch.setattr(cli_check, "run_check", boom)
    argv = ["--debug", "check", MUDDY] if where == "before" else ["check", MUDDY, "--debug"]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 3
    assert "Traceback (most recent call last)" in err
    assert 'raise ZeroDivisionError("injected")' in err
    assert err.rstrip().splitlines()[-1].startswith("epistemica: internal error")


def test_a_command_module_that_fails_to_import_is_a_bug_too(capsys, monkeypatch):
    # The command's module is imported only when it runs, inside the guard.
    monkeypatch.setitem(sys.modules, "epistemica.cli.show", None)
    code = main(["show", MUDDY])
    err = capsys.readouterr().err
    assert code == 3 and "ModuleNotFoundError" in err and "Traceback" not in err


def test_recursion_error_is_reported_as_a_bug_not_a_traceback(capsys, monkeypatch):
    def deep(args):
        return deep(args)

    monkeypatch.setattr(cli_check, "run_check", deep)
    code = main(["check", MUDDY])
    err = capsys.readouterr().err
    assert code == 3 and "RecursionError" in err and len(err.splitlines()) == 1


def test_user_errors_keep_exit_2_and_gain_a_traceback_only_with_debug(capsys):
    assert main(["check", MUDDY, "--formula", "K[c9] m1"]) == 2
    err = capsys.readouterr().err
    assert "unknown agent 'c9'" in err and "Traceback" not in err
    assert main(["check", MUDDY, "--formula", "K[c9] m1", "--debug"]) == 2
    assert "Traceback" in capsys.readouterr().err


def test_interrupt_exits_130_with_one_line(capsys, monkeypatch):
    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_plan, "run_plan", interrupted)
    code = main(["plan", MUDDY])
    err = capsys.readouterr().err
    assert code == 130 and err == "epistemica: interrupted\n"


def test_an_unwritable_output_file_is_bad_input(capsys, tmp_path):
    code = main(["show", MUDDY, "--dot", str(tmp_path / "missing" / "m.dot")])
    err = capsys.readouterr().err
    assert code == 2 and "No such file or directory" in err and "Traceback" not in err


def test_help_and_a_parse_load_no_heavy_module():
    # Not a timing test: which modules `--help` and building the parser pull in.
    heavy = ["numpy", "scipy", "networkx", "matplotlib", "oxidd", "lark", "tqdm", "distributed"]
    code = (
        "import sys, contextlib, io\n"
        "from epistemica.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try:\n"
        "        main(['--help'])\n"
        "    except SystemExit:\n"
        "        pass\n"
        f"print(sorted(m for m in {[*heavy, 'epistemica.sim', 'epistemica.aif']!r}"
        " if m in sys.modules))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


@pytest.mark.parametrize("spec", [MUDDY, str(Path(MUDDY).with_name("coin_toss.epi"))])
def test_check_does_not_load_the_simulator_or_plotting(spec):
    # numpy.ma (about 10 ms) comes with np.unique's first call; check's paths avoid it.
    code = (
        "import sys, contextlib, io\n"
        "from epistemica.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    assert main(['check', {spec!r}]) == 0\n"
        "print(sorted(m for m in ['networkx', 'matplotlib', 'tqdm', 'distributed', 'scipy',"
        " 'numpy.ma', 'oxidd', 'epistemica.sim', 'epistemica.aif'] if m in sys.modules))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


def test_the_package_root_still_exports_the_logic_layer():
    import epistemica
    from epistemica.del_ import KripkeModel

    assert epistemica.KripkeModel is KripkeModel
    assert "KripkeModel" in epistemica.__all__ and "KripkeModel" in dir(epistemica)
    assert epistemica.__version__ and epistemica.del_.evaluate is epistemica.evaluate
    with pytest.raises(AttributeError):
        epistemica.no_such_name  # noqa: B018


def _help_texts() -> dict[str, str]:
    parser = build_parser()
    texts = {"epistemica": parser.format_help()}
    for action in parser._subparsers._group_actions:  # the subcommands
        for name, sub in action.choices.items():
            texts[name] = sub.format_help()
    return texts


def test_help_cites_no_path_that_exists_only_in_a_source_checkout():
    texts = _help_texts()
    assert {"check", "plan", "show", "simulate", "sweep", "report"} <= set(texts)
    for name, text in texts.items():
        assert "docs/" not in text, name
    # The examples name spec files of the source tree, and say so.
    assert "specs/ folder of the source distribution" in texts["epistemica"]
    assert "3 an internal error" in texts["epistemica"]


def test_version_goes_to_standard_output(capsys):
    import epistemica

    with pytest.raises(SystemExit) as info:
        main(["--version"])
    out, err = capsys.readouterr()
    assert info.value.code == 0 and err == ""
    assert out == f"epistemica {epistemica.__version__}\n" and epistemica.__version__[0].isdigit()


def test_a_memory_budget_below_the_estimate_is_refused_with_the_symbolic_hint(capsys, tmp_path):
    from epistemica.cli import main

    n = 24  # 2^24 valuations: 2 MiB per truth set
    lines = [f"agents c1..c{n}", f"atoms m1..m{n}"]
    lines += [
        f"observes c{i}: " + ", ".join(f"m{j}" for j in range(1, n + 1) if j != i)
        for i in range(1, n + 1)
    ]
    lines.append("actual {m1, m2, m3}")
    spec = tmp_path / "muddy24.epi"
    spec.write_text("\n".join(lines) + "\n")
    args = ["check", str(spec), "--backend", "explicit", "--formula", "K[c1] m1 | ~K[c1] m1"]
    assert main(args) == 0
    capsys.readouterr()
    assert main([*args, "--memory-budget", "0.001"]) == 2
    err = capsys.readouterr().err
    assert "symbolic" in err and "Traceback" not in err
