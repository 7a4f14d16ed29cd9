"""``epistemica plan --implicit`` and ``--verify``: implicitly coordinated plans.

Helper of :mod:`epistemica.cli`. With ``--implicit`` the planner searches for a plan in
which the owner of every step (``action NAME by AGENT`` in the spec) knows, from its
own perspective, that the rest of the plan reaches the goal
(:func:`epistemica.del_.planning.coordination.plan_implicitly_coordinated`). ``--verify A,B,C``
checks a given plan instead: with ``--implicit`` whether it is implicitly coordinated
(and if not, which step fails, for which owner and why), without it whether it is
valid. Exit status as for the rest of the command line: 0 yes, 1 no, 2 bad input.

Examples
--------
>>> split_plan("go_r1_g1, open(a, 2),go_r2_g2")
['go_r1_g1', 'open(a, 2)', 'go_r2_g2']
>>> split_plan("go_r1_g1 go_r2_g2")
['go_r1_g1', 'go_r2_g2']
"""

from __future__ import annotations

import argparse
from typing import Any

from epistemica.cli.json_output import print_json
from epistemica.cli.plan_steps import split_plan
from epistemica.del_ import describe_model, validate
from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.del_.planning.coordination import (
    check_implicit_coordination,
    plan_implicitly_coordinated_with_stats,
)
from epistemica.del_.spec import names_hint

__all__ = ["owners_of", "plan_implicit", "print_steps", "split_plan", "verify_plan"]

EXIT_OK, EXIT_FALSE = 0, 1


def owners_of(spec: Any, file: str) -> dict[str, str]:
    """The spec's action owners; a located error naming the first action without one."""
    missing = [name for name in spec.actions if name not in spec.owners]
    if missing:
        raise SpecError(
            f"action '{missing[0]}' has no owner"
            + (f" (and {len(missing) - 1} more)" if len(missing) > 1 else ""),
            filename=file,
            hint="implicit coordination needs the agent that executes each action: declare "
            "it as 'action NAME by AGENT { ... }' (schemas: 'action go(i in agents) by i')",
        )
    return dict(spec.owners)


def _check_steps(spec: Any, steps: list[str]) -> None:

    for name in steps:
        if name not in spec.actions:
            raise InvalidArgumentError(
                f"the plan names an unknown action '{name}'",
                hint=names_hint(name, spec.actions, "action"),
            )


def _states(spec: Any, steps: list[str], validate_with: Any = None, describe: Any = None):

    run = (validate_with or validate)(spec.model, spec.actions, steps, spec.goal)
    return [(describe or describe_model)(s) for s in run.states]


def print_steps(steps: list[str], owners: dict[str, str], states: list[str] | None) -> None:
    """Print a plan's steps numbered from 1, each with its owner when ``owners`` has it.

    With ``states`` (``--explain``): the initial state first, then the state after each step.
    """
    if states is not None:
        print("initial state:")
        print(_indent(states[0]))
    for i, name in enumerate(steps, start=1):
        print(f"  {i}. {name}" + (f"  (by {owners[name]})" if name in owners else ""))
        if states is not None and i < len(states):
            print(_indent(states[i]))


def _report_json(report: Any) -> dict[str, Any]:
    return {
        "coordinated": report.coordinated,
        "reason": report.reason,
        "step": None if report.step is None else report.step + 1,
        "agent": report.agent,
        "action": report.action,
        "kind": report.kind,
        "world": None if report.world is None else str(report.world),
    }


def plan_implicit(args: argparse.Namespace, spec: Any) -> int:
    """Search for the shortest implicitly coordinated plan (breadth-first)."""

    if args.search not in (None, "bfs"):
        raise InvalidArgumentError(
            f"--implicit searches breadth-first only, not with --search {args.search}",
            hint="drop --search (implicitly coordinated plans are found by BFS)",
        )
    owners = owners_of(spec, args.file)
    result = plan_implicitly_coordinated_with_stats(
        spec.model, spec.actions, owners, spec.goal, max_depth=args.max_depth
    )
    report = None
    if result.plan is not None:
        report = check_implicit_coordination(
            spec.model, spec.actions, owners, result.plan, spec.goal
        )
    ok = report is not None and report.coordinated
    if args.json:
        out = {
            "file": args.file,
            "goal": str(spec.goal),
            "implicit": True,
            "plan": result.plan,
            "owners": None if result.plan is None else [owners[n] for n in result.plan],
            "length": result.length,
            **({"coordinated": False, "reason": None} if report is None else _report_json(report)),
            "expanded": result.expanded,
            "generated": result.generated,
            "distinct": result.distinct,
            "seconds": round(result.seconds, 6),
            "complete": result.complete,
        }
        if args.explain and result.plan is not None:
            out["states"] = _states(spec, result.plan)
        print_json("implicit-plan", out)
        return EXIT_OK if ok else EXIT_FALSE
    stats = f"bfs, {result.distinct} distinct states, {result.seconds:.3f} s"
    if result.plan is None:
        why = "exists" if result.complete else "within the search bound"
        print(f"no implicitly coordinated plan {why} for goal {spec.goal} ({stats})")
        return EXIT_FALSE
    n = result.length
    print(f"implicitly coordinated plan of {n} step{'s' if n != 1 else ''} ({stats}):")
    if args.explain:
        print_steps(result.plan, owners, _states(spec, result.plan))
    else:
        print_steps(result.plan, {}, None)
    print(("coordinated: " if ok else "NOT COORDINATED: ") + report.reason)
    return EXIT_OK if ok else EXIT_FALSE


def verify_plan(
    args: argparse.Namespace, spec: Any, validate_with: Any = None, describe: Any = None
) -> int:
    """Check the plan given with ``--verify``: implicitly coordinated, or just valid
    (by ``validate_with``, default :func:`~epistemica.del_.validate`, its states printed
    by ``describe`` with ``--explain``)."""

    validate_with, describe = validate_with or validate, describe or describe_model

    steps = split_plan(args.verify)
    _check_steps(spec, steps)
    if args.implicit:
        owners = owners_of(spec, args.file)
        report = check_implicit_coordination(spec.model, spec.actions, owners, steps, spec.goal)
        ok, reason, verdict = report.coordinated, report.reason, "implicitly coordinated"
        extra = _report_json(report)
    else:
        owners = dict(spec.owners)
        run = validate_with(spec.model, spec.actions, steps, spec.goal)
        ok, reason, verdict = run.valid, run.reason, "valid"
        # Steps count from 1 in every output, and a goal that fails only at the end is
        # charged to the last step, as --implicit does (Validation.step is 0-based and
        # points past the plan then).
        step = None if run.step is None else min(run.step + 1, len(steps))
        extra = {"valid": run.valid, "reason": run.reason, "step": step}
    if args.json:
        out = {"file": args.file, "goal": str(spec.goal), "implicit": args.implicit}
        out.update({"plan": steps, **extra})
        if args.explain:
            out["states"] = _states(spec, steps, validate_with, describe)
        print_json("implicit-plan", out)
        return EXIT_OK if ok else EXIT_FALSE
    print(f"plan {', '.join(steps)}: {'' if ok else 'not '}{verdict}")
    if args.explain:
        print_steps(steps, owners, _states(spec, steps, validate_with, describe))
    print(f"  {reason}")
    return EXIT_OK if ok else EXIT_FALSE


def _indent(text: str) -> str:
    return "\n".join("       " + line for line in text.splitlines())
