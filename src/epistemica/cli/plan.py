"""``epistemica plan``: search for a plan reaching the spec's goal, or check one.

Helper of :mod:`epistemica.cli`, imported only when the command runs; ``--implicit`` and
``--verify`` are in :mod:`epistemica.cli.coordination`. Plan steps are numbered from 1 in
every output, text and JSON alike. Exit status 0 when a (valid) plan was found, 1 when no
plan exists or the plan is not valid.

``--backend``: ``explicit`` searches over Kripke models, ``symbolic`` over knowledge
structures (:mod:`epistemica.del_.planning.symbolic_search`), ``auto`` (the default) the
explicit one unless its estimate for the spec's atoms exceeds the memory budget.
"""

from __future__ import annotations

import argparse
from typing import Any

from epistemica.cli.coordination import plan_implicit, print_steps, verify_plan
from epistemica.cli.exit import EXIT_FALSE, EXIT_OK
from epistemica.cli.inputs import is_foreign, load_input, plank_line
from epistemica.cli.json_output import print_json
from epistemica.cli.policy import plan_policy_command, verify_policy_command
from epistemica.del_ import KripkeModel, describe_model, parse_spec, plan_with_stats, validate
from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.del_.planning.symbolic_search import (
    choose_backend,
    plan_symbolic_with_stats,
    validate_symbolic,
)
from epistemica.input_files import read_input

__all__ = ["load_for_planning", "run_plan"]


def load_for_planning(path: str, backend: str = "auto") -> tuple[Any, str]:
    """The spec with its model for ``backend``, and the backend chosen (``explicit`` or
    ``symbolic``); ``auto`` asks :func:`~epistemica.del_.planning.symbolic_search.choose_backend`
    about the spec's atoms and agents."""

    text = read_input(path, "plan")[1]  # read once, bounded
    spec = parse_spec(text, path, "symbolic" if backend == "symbolic" else "auto")
    if backend == "symbolic":
        return spec, "symbolic"
    if isinstance(spec.model, KripkeModel):
        return spec, "explicit"
    if backend == "auto" and choose_backend(len(spec.atoms), len(spec.agents)) == "symbolic":
        return spec, "symbolic"
    return parse_spec(text, path, "explicit"), "explicit"


def run_plan(args: argparse.Namespace) -> int:
    """Run ``epistemica plan`` with parsed arguments; return the exit status."""
    task = None
    if is_foreign(args):
        spec, task = load_input(args, "explicit", "plan")  # planned on Kripke models
        backend = "explicit"
    else:
        spec, backend = load_for_planning(args.file, getattr(args, "backend", "auto"))
    spec.require_goal()
    if not spec.actions:
        raise SpecError(
            "the spec has no actions",
            filename=args.file,
            hint="declare 'action' lines to plan with",
        )
    policy = _check_options(args, spec, backend)
    if policy:
        command = plan_policy_command if args.verify is None else verify_policy_command
        return command(args, spec)
    plan_with, validate_with, describe = plan_with_stats, validate, describe_model
    if backend == "symbolic":
        plan_with, validate_with, describe = plan_symbolic_with_stats, validate_symbolic, summary
    if args.verify is not None:
        return verify_plan(args, spec, validate_with, describe)
    if args.implicit:
        return plan_implicit(args, spec)
    result = plan_with(
        spec.model, spec.actions, spec.goal, search=args.search or "bfs", max_depth=args.max_depth
    )
    check = (
        None
        if result.plan is None
        else validate_with(spec.model, spec.actions, result.plan, spec.goal)
    )
    states = [] if check is None else [describe(s) for s in check.states]
    if args.json:
        return _print_json(args, spec, backend, task, result, check, states)
    return _print_text(args, spec, backend, task, result, check, states)


def _check_options(args: argparse.Namespace, spec: Any, backend: str) -> bool:
    """Refuse combinations of options that mean nothing; whether a policy is asked for."""
    policy = getattr(args, "policy", False)
    if policy and not args.implicit:
        raise InvalidArgumentError(
            "--policy is a kind of implicitly coordinated plan",
            hint="use it with --implicit (and --verify to check a plan as a policy)",
        )
    if getattr(args, "perspective", None) is not None and not policy:
        raise InvalidArgumentError(
            "--perspective is for policies", hint="use it with --implicit --policy"
        )
    if args.implicit and backend == "symbolic":
        raise InvalidArgumentError(
            "implicit coordination is planned over Kripke models only",
            hint="use --backend explicit (or a smaller spec, or a larger --memory-budget)",
        )
    if policy and args.perspective is not None and args.perspective not in spec.agents:
        raise InvalidArgumentError(
            f"unknown agent {args.perspective!r} for --perspective",
            hint=f"agents: {', '.join(spec.agents)}",
        )
    return policy


def _print_json(args, spec, backend: str, task, result, check, states: list) -> int:
    ok = check is not None and check.valid
    out = {
        "file": args.file,
        "goal": str(spec.goal),
        "search": result.search,
        "backend": backend,
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
    if task is not None and result.plan is not None:
        out["plank_plan"] = task.plank_plan(result.plan)
    if args.explain:
        out["states"] = states
    print_json("plan", out)
    return EXIT_OK if ok else EXIT_FALSE


def _print_text(args, spec, backend: str, task, result, check, states: list) -> int:
    stats = f"{result.search}, {result.distinct} distinct states, {result.seconds:.3f} s"
    if backend == "symbolic":
        stats = f"symbolic, {stats}"
    if result.plan is None:
        why = "no plan exists" if result.complete else "no plan within the search bound"
        print(f"{why} for goal {spec.goal} ({stats})")
        return EXIT_FALSE
    ok = check is not None and check.valid
    print(f"plan of {result.length} step{'s' if result.length != 1 else ''} ({stats}):")
    print_steps(result.plan, {}, states if args.explain else None)
    print(("validated: " if ok else "INVALID: ") + check.reason)
    if task is not None:
        print(plank_line(task, result.plan))
    return EXIT_OK if ok else EXIT_FALSE


def summary(structure: Any) -> str:
    """One line about a knowledge structure (``--explain`` of the symbolic backend)."""
    return (
        f"{structure.n_worlds} states ({structure.count_designated()} designated), "
        f"{structure.n_variables} variables, atoms: {', '.join(structure.atoms)}"
    )
