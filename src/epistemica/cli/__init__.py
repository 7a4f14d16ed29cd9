"""The ``epistemica`` command-line interface.

Commands:

- ``epistemica check FILE``: evaluate every ``check`` claim of a spec file;
  ``epistemica check FILE --formula F``: whether ``F`` holds at the designated worlds and
  where it holds;
- ``epistemica plan FILE``: search for a plan reaching the spec's ``goal``;
  ``--implicit``: an implicitly coordinated plan (each action's owner knows the rest of
  the plan works); ``--verify A,B,C``: check a given plan instead (valid, or with
  ``--implicit`` implicitly coordinated, and why not); plan steps count from 1;
- ``check``, ``plan`` and ``show`` also read an EPDDL task (``DOMAIN PROBLEM -l LIB``) and
  SMCDEL's text format; ``epistemica export --epddl|--smcdel SPEC`` writes a spec in them;
- ``epistemica show FILE``: the spec's model, optionally ``--after`` some of its actions,
  as text, Graphviz DOT or JSON (which :func:`epistemica.model_json.model_from_json`
  reads back);
- ``epistemica run MISSION``: a mission file's study (table, figure, animation);
  ``check`` also reads mission files (``--after STEPS``: after a seeded trial's events);
- ``epistemica simulate``, ``sweep``, ``report``: the multi-robot simulator;
- ``epistemica view FILE``: a trial's replay as a self-contained HTML page
  (``show --html`` writes one for a spec's model).

Exit status (grep-like, so that shell scripts can branch on it; see
:mod:`epistemica.cli.exit`): 0 on success, 1 when a claim (or --expect) is false or no plan
exists, 2 on bad input, printed as ``FILE:LINE:COL: error: ...`` plus a hint, 3 on an
internal error (a bug: one line, the traceback only with ``--debug``). ``--json`` prints
one JSON object on standard output instead of text.

Start-up is kept short: this module imports only argparse, and each command's module
(with numpy, scipy, lark, ...) is imported when that command runs.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from epistemica.cli.arguments import (
    add_check_options,
    add_run_command,
    add_simulate_command,
    add_sweep_commands,
    add_view_command,
)
from epistemica.cli.exit import EXIT_USAGE, guarded
from epistemica.cli.formats import add_export_command, add_input_options
from epistemica.cli.generate_arguments import add_generate_command
from epistemica.del_.budget import budget_scope

__all__ = ["COMMANDS", "build_parser", "main"]

#: Each command's handler, ``"module:function"``: a module is imported when its command
#: runs, so that start-up (and ``--help``) pays only for argparse.
COMMANDS = {
    "check": "epistemica.cli.check:run_check",
    "plan": "epistemica.cli.plan:run_plan",
    "show": "epistemica.cli.show:run_show",
    "run": "epistemica.cli.run:run_mission",
    "simulate": "epistemica.cli.simulate:run_simulate",
    "sweep": "epistemica.cli.sweep:run_sweep_command",
    "report": "epistemica.cli.sweep:run_report",
    "export": "epistemica.cli.export:run_export",
    "view": "epistemica.view:run_view",
    "generate": "epistemica.cli.generate:run_generate",
}

_EPILOG = """\
examples:
  epistemica run specs/rendezvous.epi
  epistemica check specs/puzzles/muddy_children.epi
  epistemica check specs/puzzles/muddy_children.epi --formula "[father] K[c1] m1"
  epistemica check specs/puzzles/sally_anne.epi --json
  epistemica plan specs/puzzles/muddy_children.epi --explain
  epistemica plan specs/puzzles/muddy_children.epi --search astar --max-depth 5 --json
  epistemica plan specs/planning/two_robots_implicit.epi --implicit --explain
  epistemica plan specs/planning/two_robots_implicit.epi --implicit --verify go_r2_g2,go_r1_g1
  epistemica show specs/puzzles/muddy_children.epi --after father,nobody_knows
  epistemica show specs/puzzles/sally_anne.epi --after sally_leaves --dot sally.dot
  epistemica show specs/puzzles/muddy_children.epi --html muddy.html
  epistemica plan DOMAIN.epddl PROBLEM.epddl -l LIBRARY.epddl
  epistemica export --epddl specs/planning/grapevine.epi -o out/
  epistemica simulate --mission allocation --robots 4 --seed 2 --reasoning third --gif t.gif
  epistemica sweep --mission rendezvous --robots 2..5 --trials 50 --out runs/study.sqlite
  epistemica report runs/study.sqlite --markdown
  epistemica view specs/rendezvous.epi --trial 3 -o trial.html
(the spec files named here are in the specs/ folder of the source distribution)

exit status: 0 success, 1 a claim (or --expect) is false, no plan exists or a simulated
mission failed, 2 bad input, 3 an internal error (a bug; --debug shows the traceback),
130 interrupted
"""


class _Parser(argparse.ArgumentParser):
    """argparse exits with 2 on usage errors already; keep its message short and hinted."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\nhint: run '{self.prog} --help'\n")


def _depth(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {text!r}")
    return value


class _Version(argparse.Action):
    """``--version``, looked up only when asked for (importlib.metadata is slow to import)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, **kw):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, **kw)

    def __call__(self, parser, namespace, values, option_string=None):
        from importlib.metadata import PackageNotFoundError, version

        try:
            number = version("epistemica")  # one source of truth: pyproject.toml
        except PackageNotFoundError:  # a source tree that was never installed
            number = "0+unknown"
        print(f"epistemica {number}")  # on standard output, as argparse's own
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of the ``epistemica`` command."""
    parser = _Parser(
        prog="epistemica",
        description="Epistemic planning and active-inference coordination for multi-robot teams.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action=_Version, help="print the version and exit")
    parser.add_argument("--debug", action="store_true", help=_DEBUG_HELP)
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    _add_check(commands)
    _add_plan(commands)
    _add_show(commands)
    add_run_command(commands)
    add_simulate_command(commands)
    add_sweep_commands(commands)
    add_view_command(commands)
    for name in ("check", "plan", "show"):
        add_input_options(commands.choices[name])
    add_export_command(commands)
    add_generate_command(commands)
    for name in ("check", "plan", "show"):
        commands.choices[name].add_argument(
            "--memory-budget",
            type=_gibibytes,
            default=None,
            metavar="GIB",
            help="refuse explicit-model work estimated above GIB gibibytes (default 4); "
            "the error names the symbolic backend",
        )
    for command in commands.choices.values():
        # Also after the command (`epistemica check F --debug`); SUPPRESS keeps the
        # top-level value when the flag is not repeated there.
        command.add_argument(
            "--debug", action="store_true", default=argparse.SUPPRESS, help=_DEBUG_HELP
        )
    return parser


def _gibibytes(text: str) -> int:
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not 0 < value <= 1024:
        raise argparse.ArgumentTypeError(f"expected a size in GiB in (0, 1024], got {text!r}")
    return int(value * 2**30)


_DEBUG_HELP = "print the traceback of any error (for reporting a bug)"


def _add_check(commands) -> None:
    check = commands.add_parser(
        "check",
        help="evaluate the claims of a spec or mission file, or one formula",
        description="Evaluate every 'check' claim of a spec file (exit 1 if one fails), or, "
        "with --formula, whether a formula holds at the designated worlds (exit 0 either "
        "way; with --expect, exit 1 if the answer differs).",
        epilog="examples:\n"
        "  epistemica check specs/puzzles/muddy_children.epi\n"
        '  epistemica check specs/puzzles/coin_toss.epi --formula "[toss][show_b] Kw[b] heads"\n',
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    check.add_argument("file", metavar="FILE", help="a spec file or a mission file (.epi)")
    check.add_argument("--formula", "-f", metavar="F", help="check this formula instead")
    check.add_argument(
        "--expect",
        choices=("true", "false"),
        help="with --formula: exit 1 unless the formula is true (false) as expected",
    )
    check.add_argument("--json", action="store_true", help="print a JSON object")
    check.add_argument(
        "--where",
        action="store_true",
        help="with --formula: list the worlds (states) where it holds, --limit of them",
    )
    check.add_argument(
        "--limit", type=_positive, metavar="N", help="with --where: list at most N (default 100)"
    )
    _add_backend(check)
    add_check_options(check)


def _add_backend(command) -> None:
    command.add_argument(
        "--backend",
        choices=("auto", "explicit", "symbolic"),
        default="auto",
        help="explicit Kripke model or BDD knowledge structure (default auto: symbolic "
        "above 20 observed atoms or 2^20 worlds)",
    )


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if not 0 < value <= 10**9:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return value


def _add_plan(commands) -> None:
    plan = commands.add_parser(
        "plan",
        help="find a sequence of actions reaching the spec's goal",
        description="Search for a plan (a sequence of the spec's actions) after which the "
        "spec's goal holds at every designated world; the plan is validated step by step. "
        "Steps are numbered from 1 in every output, text and JSON.",
        epilog="examples:\n"
        "  epistemica plan specs/puzzles/muddy_children.epi --explain\n"
        "  epistemica plan specs/puzzles/muddy_children.epi --search astar --json\n"
        "  epistemica plan specs/planning/two_robots_implicit.epi --implicit --explain\n"
        "  epistemica plan specs/planning/two_robots_implicit.epi --implicit "
        "--verify go_r2_g2,go_r1_g1\n",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    plan.add_argument("file", metavar="SPEC", help="a spec file with a 'goal' line")
    plan.add_argument(
        "--search", choices=("bfs", "astar", "greedy"), help="search strategy (default: bfs)"
    )
    plan.add_argument("--max-depth", type=_depth, metavar="N", help="longest plan to try")
    plan.add_argument(
        "--explain",
        action="store_true",
        help="print the epistemic state after each step (and, with --implicit, who acts)",
    )
    plan.add_argument(
        "--implicit",
        action="store_true",
        help="find an implicitly coordinated plan; actions need owners ('action NAME by AGENT')",
    )
    plan.add_argument(
        "--verify",
        metavar="A,B,C",
        help="check this plan (comma-separated actions) instead of searching; with "
        "--implicit, whether it is implicitly coordinated and why not",
    )
    plan.add_argument("--json", action="store_true", help="print a JSON object")
    plan.add_argument(
        "--backend",
        choices=("auto", "explicit", "symbolic"),
        default="auto",
        help="search over Kripke models or over BDD knowledge structures (default auto: "
        "symbolic when the explicit model would exceed the memory budget)",
    )
    plan.add_argument(
        "--policy",
        action="store_true",
        help="with --implicit: a policy that branches on what the acting agent observes "
        "(printed as a tree); with --verify, check a policy (a JSON file written by "
        "--policy --json, or a plan A,B,C) against that definition",
    )
    plan.add_argument(
        "--perspective",
        metavar="AGENT",
        help="with --implicit --policy: plan (or verify) from this agent's perspective on the "
        "initial state, every world it considers possible designated",
    )


def _add_show(commands) -> None:
    show = commands.add_parser(
        "show",
        help="print a spec's model (after some of its actions) as text, DOT or JSON",
        description="Print the model of a spec file, optionally after a sequence of its "
        "actions (product update), with the worlds, agents and atoms named as in the spec. "
        "--json prints a JSON object that epistemica.model_json.model_from_json reads back.",
        epilog="examples:\n"
        "  epistemica show specs/puzzles/muddy_children.epi\n"
        "  epistemica show specs/puzzles/muddy_children.epi --after father,nobody_knows\n"
        "  epistemica show specs/puzzles/sally_anne.epi --after 'sally_leaves anne_moves' "
        "--dot sally.dot\n",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    show.add_argument("file", metavar="SPEC", help="a spec file (.epi)")
    show.add_argument(
        "--after",
        metavar="ACTIONS",
        default="",
        help="actions to apply first, separated by commas or spaces",
    )
    output = show.add_mutually_exclusive_group()
    output.add_argument("--dot", metavar="FILE", help="write the model as Graphviz DOT to FILE")
    output.add_argument("--json", action="store_true", help="print the model as JSON")
    output.add_argument(
        "--html",
        metavar="FILE",
        help="write a self-contained page: worlds, relations, claims, a formula box",
    )
    show.add_argument(
        "--force", action="store_true", help="replace an existing --dot or --html file"
    )
    show.add_argument(
        "--limit",
        type=_positive,
        metavar="N",
        help="list at most N worlds (text, DOT, JSON) or states (symbolic); default 16 in "
        "text, every world in DOT and JSON",
    )
    _add_backend(show)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit status.

    See :mod:`epistemica.cli.exit` for the statuses.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return EXIT_USAGE
    return guarded(_handler(COMMANDS[args.command]), args)


def _handler(where: str):
    """The handler ``"module:function"``, its module imported only now, when it runs."""

    def run(args: argparse.Namespace) -> int:
        module, _, name = where.partition(":")
        function = getattr(importlib.import_module(module), name)
        budget = getattr(args, "memory_budget", None)
        if budget is None:
            return function(args)
        with budget_scope(budget):
            return function(args)

    return run
