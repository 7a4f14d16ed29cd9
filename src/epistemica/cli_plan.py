"""``epistemica plan``: search for a plan reaching the spec's goal, or check one.

Helper of :mod:`epistemica.cli`, imported only when the command runs; ``--implicit`` and
``--verify`` are in :mod:`epistemica.cli_coordination`. Plan steps are numbered from 1 in
every output, text and JSON alike. Exit status 0 when a (valid) plan was found, 1 when no
plan exists or the plan is not valid.
"""

from __future__ import annotations

import argparse
import json

from epistemica.cli_coordination import plan_implicit, print_steps, verify_plan
from epistemica.cli_exit import EXIT_FALSE, EXIT_OK
from epistemica.del_ import describe_model, parse_spec, plan_with_stats, validate
from epistemica.del_.errors import SpecError
from epistemica.input_files import read_input

__all__ = ["run_plan"]


def run_plan(args: argparse.Namespace) -> int:
    """Run ``epistemica plan`` with parsed arguments; return the exit status."""
    # Planning lists states: the explicit backend (a spec too large for it is refused).
    spec = parse_spec(read_input(args.file, "plan")[1], args.file, backend="explicit")
    spec.require_goal()
    if not spec.actions:
        raise SpecError(
            "the spec has no actions",
            filename=args.file,
            hint="declare 'action' lines to plan with",
        )
    if args.verify is not None or args.implicit:
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
    print_steps(result.plan, {}, states if args.explain else None)
    print(("validated: " if ok else "INVALID: ") + check.reason)
    return EXIT_OK if ok else EXIT_FALSE
