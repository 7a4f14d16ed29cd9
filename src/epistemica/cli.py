"""The ``epistemica`` command-line interface.

Commands:

- ``epistemica check FILE``: evaluate every ``check`` claim of a spec file;
  ``epistemica check FILE --formula F``: whether ``F`` holds at the designated worlds and
  where it holds;
- ``epistemica plan FILE``: search for a plan reaching the spec's ``goal``;
  ``--implicit``: an implicitly coordinated plan (each action's owner knows the rest of
  the plan works); ``--verify A,B,C``: check a given plan instead (valid, or with
  ``--implicit`` implicitly coordinated, and why not).

Exit status (grep-like, so that shell scripts can branch on it): 0 on success (every claim
as expected, the formula holds, a plan was found), 1 when a claim fails, the formula does
not hold or no plan exists, 2 on bad input (a malformed spec, an unknown name, a bad
option), with the error printed as ``FILE:LINE:COL: error: ...`` plus a hint and never a
Python traceback. ``--json`` prints one JSON object on standard output instead of text.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from typing import Any

from epistemica import __version__
from epistemica.del_.errors import EpistemicaError, InvalidArgumentError, SpecError

__all__ = ["build_parser", "main"]

EXIT_OK, EXIT_FALSE, EXIT_USAGE = 0, 1, 2

# Worlds listed by `check --formula` before "... and N more" (text) / truncation (JSON).
_LIST_TEXT, _LIST_JSON = 12, 1000

_EPILOG = """\
examples:
  epistemica check specs/puzzles/muddy_children.epi
  epistemica check specs/puzzles/muddy_children.epi --formula "[father] K[c1] m1"
  epistemica check specs/puzzles/sally_anne.epi --json
  epistemica plan specs/puzzles/muddy_children.epi --explain
  epistemica plan specs/puzzles/muddy_children.epi --search astar --max-depth 5 --json
  epistemica plan specs/planning/two_robots_implicit.epi --implicit --explain
  epistemica plan specs/planning/two_robots_implicit.epi --implicit --verify go_r2_g2,go_r1_g1
  epistemica simulate --mission allocation --robots 4 --seed 2 --reasoning third --gif t.gif
  epistemica sweep --mission rendezvous --robots 2..5 --trials 50 --out runs/study.sqlite
  epistemica report runs/study.sqlite --markdown

exit status: 0 success, 1 a claim or formula is false, no plan exists or a simulated
mission failed, 2 bad input
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


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of the ``epistemica`` command."""
    parser = _Parser(
        prog="epistemica",
        description="Epistemic planning and active-inference coordination for multi-robot teams.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"epistemica {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    check = commands.add_parser(
        "check",
        help="evaluate the claims of a spec file, or one formula",
        description="Evaluate every 'check' claim of a spec file (exit 1 if one fails), or, "
        "with --formula, whether a formula holds at the designated worlds (exit 1 if not).",
        epilog="examples:\n"
        "  epistemica check specs/puzzles/muddy_children.epi\n"
        '  epistemica check specs/puzzles/coin_toss.epi --formula "[toss][show_b] Kw[b] heads"\n',
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    check.add_argument("file", metavar="FILE", help="a spec file (.epi)")
    check.add_argument("--formula", "-f", metavar="F", help="check this formula instead")
    check.add_argument("--json", action="store_true", help="print a JSON object")
    check.add_argument(
        "--backend",
        choices=("auto", "explicit", "symbolic"),
        default="auto",
        help="explicit Kripke model or BDD knowledge structure (default auto: symbolic "
        "above 20 observed atoms)",
    )
    from epistemica.cli_run import add_check_options

    add_check_options(check)
    check.set_defaults(handler=_check)

    plan = commands.add_parser(
        "plan",
        help="find a sequence of actions reaching the spec's goal",
        description="Search for a plan (a sequence of the spec's actions) after which the "
        "spec's goal holds at every designated world; the plan is validated step by step.",
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
    plan.set_defaults(handler=_plan)
    from epistemica.cli_run import add_command as add_run_command
    from epistemica.cli_simulate import add_command as add_simulate_command
    from epistemica.cli_sweep import add_commands as add_sweep_commands

    add_run_command(commands)
    add_simulate_command(commands)
    add_sweep_commands(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handler = getattr(args, "handler", None)
    if handler is None:
        parser.print_help()
        return EXIT_USAGE
    try:
        return int(handler(args))
    except EpistemicaError as err:
        print(err, file=sys.stderr)
        return EXIT_USAGE


# --------------------------------------------------------------------------------------
# check
# --------------------------------------------------------------------------------------


def _world(model: Any, world: Any, labels: dict) -> dict[str, Any]:
    true = model.valuation_of(world)
    return {"world": labels[world], "atoms": [a for a in model.atoms if a in true]}


def _show(entry: dict[str, Any]) -> str:
    return f"{entry['world']} {{{', '.join(entry['atoms'])}}}"


def _check(args: argparse.Namespace) -> int:
    from epistemica.cli_run import check_mission, is_mission_file
    from epistemica.del_.symbolic.backend import load_spec

    if is_mission_file(args.file):
        return check_mission(args)
    if args.after is not None or args.robot is not None:
        raise InvalidArgumentError(
            "--after and --robot apply to mission files", hint="a file starting with 'mission'"
        )

    spec = load_spec(args.file, args.backend)
    if args.formula is not None:
        return _check_formula(spec, args)
    results = [(c, spec.holds(c.formula)) for c in spec.checks]
    failed = [c for c, value in results if value != c.expected]
    if args.json:
        claims = [
            {
                "name": c.name,
                "formula": c.text,
                "expected": c.expected,
                "holds": value,
                "ok": value == c.expected,
                "line": c.line,
                "column": c.column,
            }
            for c, value in results
        ]
        out = {"file": args.file, "claims": claims, "passed": len(results) - len(failed)}
        print(json.dumps({**out, "failed": len(failed)}, indent=2))
        return EXIT_FALSE if failed else EXIT_OK
    model = spec.model
    print(
        f"{args.file}: {len(results)} claim{'s' if len(results) != 1 else ''}; "
        f"{model.n_worlds} worlds, agents {', '.join(spec.agents)}"
    )
    if not results:
        print("no claims: add 'check \"name\": FORMULA' lines, or pass --formula")
    for c, value in results:
        verdict = "true " if value else "false"
        if value == c.expected:
            print(f"  ok    {verdict}  {c.name}")
        else:
            print(f"  FAIL  {verdict}  {c.name}  (expected {str(c.expected).lower()})")
            print(f"        {c.location}: {c.text}")
    print(f"{len(results) - len(failed)} passed, {len(failed)} failed")
    return EXIT_FALSE if failed else EXIT_OK


def _check_formula(spec: Any, args: argparse.Namespace) -> int:
    from epistemica.del_.describe import world_labels

    formula = spec.formula(args.formula)
    model = spec.model
    if not hasattr(model, "truth_set"):  # a KnowledgeStructure: it lists no worlds
        return _check_formula_symbolic(spec, formula, args)
    labels = world_labels(model)
    where = model.truth_set(formula, actions=spec.actions)
    designated = [{**_world(model, w, labels), "holds": w in where} for w in model.designated]
    holds = all(d["holds"] for d in designated)
    true_worlds = [w for w in model.worlds if w in where]
    if args.json:
        listed = [_world(model, w, labels) for w in true_worlds[:_LIST_JSON]]
        print(
            json.dumps(
                {
                    "file": args.file,
                    "formula": str(formula),
                    "holds": holds,
                    "designated": designated,
                    "n_worlds": model.n_worlds,
                    "n_true": len(true_worlds),
                    "worlds": listed,
                    "truncated": len(true_worlds) > len(listed),
                },
                indent=2,
            )
        )
        return EXIT_OK if holds else EXIT_FALSE
    print(f"{formula}")
    print(f"  {'true' if holds else 'false'} at the designated world", end="")
    if len(designated) == 1:
        print(f" {_show(designated[0])}")
    else:
        n_ok = sum(d["holds"] for d in designated)
        print(f"s: holds at {n_ok} of {len(designated)}")
        for d in designated[:_LIST_TEXT]:
            print(f"    {'true ' if d['holds'] else 'false'}  {_show(d)}")
    shown = ", ".join(_show(_world(model, w, labels)) for w in true_worlds[:_LIST_TEXT])
    more = len(true_worlds) - _LIST_TEXT
    tail = f", ... and {more} more" if more > 0 else ""
    print(f"  holds at {len(true_worlds)} of {model.n_worlds} worlds" + (":" if shown else ""))
    if shown:
        print(f"    {shown}{tail}")
    return EXIT_OK if holds else EXIT_FALSE


def _check_formula_symbolic(spec: Any, formula: Any, args: argparse.Namespace) -> int:
    """Counts instead of world lists: a knowledge structure does not list its states."""
    from epistemica.del_.symbolic.backend import formula_summary

    summary = formula_summary(spec, formula)
    if args.json:
        print(json.dumps({"file": args.file, "formula": str(formula), **summary}, indent=2))
        return EXIT_OK if summary["holds"] else EXIT_FALSE
    print(f"{formula}")
    print(
        f"  {'true' if summary['holds'] else 'false'} at the designated worlds: holds at "
        f"{summary['n_designated_true']} of {summary['n_designated']}"
    )
    print(f"  holds at {summary['n_true']} of {summary['n_worlds']} worlds (symbolic backend)")
    return EXIT_OK if summary["holds"] else EXIT_FALSE


# --------------------------------------------------------------------------------------
# plan
# --------------------------------------------------------------------------------------


def _plan(args: argparse.Namespace) -> int:
    from epistemica.del_.describe import describe_model
    from epistemica.del_.planner import plan_with_stats, validate
    from epistemica.del_.spec import load_spec

    spec = load_spec(args.file)
    if spec.goal is None:
        raise SpecError(
            "the spec has no goal",
            filename=args.file,
            hint="add a line such as 'goal K[a] p' to plan for",
        )
    if not spec.actions:
        raise SpecError(
            "the spec has no actions",
            filename=args.file,
            hint="declare 'action' lines to plan with",
        )
    if args.verify is not None or args.implicit:
        from epistemica.cli_coordination import plan_implicit, verify_plan

        return verify_plan(args, spec) if args.verify is not None else plan_implicit(args, spec)
    result = plan_with_stats(
        spec.model, spec.actions, spec.goal, search=args.search or "bfs", max_depth=args.max_depth
    )
    check = (
        None if result.plan is None else validate(spec.model, spec.actions, result.plan, spec.goal)
    )
    states = [] if check is None else [describe_model(s) for s in check.states]
    ok = check is not None and check.valid
    if args.json:
        out = {
            "file": args.file,
            "goal": str(spec.goal),
            "search": result.search,
            "plan": result.plan,
            "length": result.length,
            "valid": ok,
            "reason": None if check is None else check.reason,
            "expanded": result.expanded,
            "generated": result.generated,
            "distinct": result.distinct,
            "seconds": round(result.seconds, 6),
            "complete": result.complete,
        }
        if args.explain:
            out["states"] = states
        print(json.dumps(out, indent=2))
        return EXIT_OK if ok else EXIT_FALSE
    stats = f"{result.search}, {result.distinct} distinct states, {result.seconds:.3f} s"
    if result.plan is None:
        why = "no plan exists" if result.complete else "no plan within the search bound"
        print(f"{why} for goal {spec.goal} ({stats})")
        return EXIT_FALSE
    print(f"plan of {result.length} step{'s' if result.length != 1 else ''} ({stats}):")
    if args.explain:
        print("initial state:")
        print(_indent(states[0]))
    for i, name in enumerate(result.plan, start=1):
        print(f"  {i}. {name}")
        if args.explain and i < len(states):
            print(_indent(states[i]))
    print(("validated: " if ok else "INVALID: ") + check.reason)
    return EXIT_OK if ok else EXIT_FALSE


def _indent(text: str) -> str:
    return "\n".join("       " + line for line in text.splitlines())
