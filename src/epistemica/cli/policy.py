"""``epistemica plan --implicit --policy``: implicitly coordinated policies.

Helper of :mod:`epistemica.cli.plan`. ``--policy`` searches for a policy that branches on
what the acting agent observes (:func:`epistemica.del_.planning.policy.plan_policy`) and
prints it as a tree, one decision a line, children indented under the decision they
follow::

    r1, when it knows target1: go_r1_g1
      r2: go_r2_g2

``--verify`` checks a policy instead: a JSON file as ``--policy --json`` writes it, or a
plan ``A,B,C`` read as a policy without branching. ``--perspective AGENT`` plans (or
checks) from that agent's perspective on the initial state. Exit status 0 when a policy
was found (or holds), 1 when none exists (or it fails), 2 on bad input.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from epistemica.cli.coordination import owners_of
from epistemica.cli.exit import EXIT_FALSE, EXIT_OK
from epistemica.cli.json_output import print_json
from epistemica.cli.plan_steps import split_plan
from epistemica.del_ import Top
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.planning.policy import Decision, Policy, check_policy, plan_policy
from epistemica.del_.spec import check_token_count, names_hint, read_source

__all__ = ["MAX_POLICY_BYTES", "plan_policy_command", "verify_policy_command"]

#: Larger policy files are refused (a policy `plan --json` writes is a few kB).
MAX_POLICY_BYTES = 16 << 20


def plan_policy_command(args: argparse.Namespace, spec: Any) -> int:
    """Search for a least-depth implicitly coordinated policy and print it."""

    owners = owners_of(spec, args.file)
    depth = args.max_depth if args.max_depth is not None else 12
    result = plan_policy(spec.model, spec.actions, owners, spec.goal, depth, args.perspective)
    report = None
    if result.policy is not None:
        report = check_policy(
            spec.model, spec.actions, owners, spec.goal, result.policy, args.perspective
        )
    ok = report is not None and report.ok
    if args.json:
        out = {
            **_header(args, spec),
            **({} if result.policy is None else result.policy.to_dict()),
            "depth": None if result.policy is None else result.policy.depth,
            "decisions": None if result.policy is None else result.policy.size,
            "coordinated": ok,
            "reason": None if report is None else report.reason,
            "local_states": result.local_states,
            "seconds": round(result.seconds, 6),
            "complete": result.complete,
        }
        print_json("policy", out)
        return EXIT_OK if ok else EXIT_FALSE
    stats = f"{result.local_states} local states, {result.seconds:.3f} s"
    if result.policy is None:
        why = "exists" if result.complete else f"of depth at most {depth}"
        print(f"no implicitly coordinated policy {why} for goal {spec.goal} ({stats})")
        return EXIT_FALSE
    policy = result.policy
    print(
        f"implicitly coordinated policy of depth {policy.depth}, {policy.size} decision"
        f"{'s' if policy.size != 1 else ''} ({stats}):"
    )
    print(_indent(str(policy)))
    print(("coordinated: " if ok else "NOT COORDINATED: ") + report.reason)
    return EXIT_OK if ok else EXIT_FALSE


def verify_policy_command(args: argparse.Namespace, spec: Any) -> int:
    """Check the policy (or plan) given with ``--verify`` and say why it fails."""

    owners = owners_of(spec, args.file)
    policy = _read_policy(args.verify, spec, owners, Decision, Policy)
    report = check_policy(spec.model, spec.actions, owners, spec.goal, policy, args.perspective)
    if args.json:
        out = {
            **_header(args, spec),
            **policy.to_dict(),
            "coordinated": report.ok,
            "reason": report.reason,
            "where": list(report.path),
        }
        print_json("policy", out)
        return EXIT_OK if report.ok else EXIT_FALSE
    print(f"policy of depth {policy.depth}: {'' if report.ok else 'not '}implicitly coordinated")
    print(_indent(str(policy)))
    print(f"  {report.reason}")
    if report.path:
        print(f"  at: {' / '.join(report.path)}")
    return EXIT_OK if report.ok else EXIT_FALSE


def _read_policy(text: str, spec: Any, owners: dict[str, str], decision, policy_class):
    """A policy from a JSON file, or from a plan read as a policy without branches."""
    path = Path(text)
    if text.endswith(".json") or path.is_file():
        # bounded in bytes and tokens (its 'when' formulas are parsed), binary-checked
        source = read_source(path, "policy file", MAX_POLICY_BYTES)
        check_token_count(source, str(path), "policy file")
        try:
            return policy_class.from_dict(json.loads(source))
        except InvalidArgumentError:  # from_dict's own, with its hint
            raise
        except (ValueError, RecursionError) as error:  # RecursionError: nested too deeply
            raise InvalidArgumentError(
                f"cannot read the policy {text!r}: {error}",
                hint="give the JSON written by `epistemica plan SPEC --implicit --policy --json`",
            ) from None
    steps = split_plan(text)
    for name in steps:
        if name not in spec.actions:
            raise InvalidArgumentError(
                f"the plan names an unknown action '{name}'",
                hint=names_hint(name, spec.actions, "action"),
            )

    chain: tuple = ()
    for name in reversed(steps):
        chain = (decision(owners[name], Top(), name, chain),)
    return policy_class(chain)


def _header(args: argparse.Namespace, spec: Any) -> dict[str, Any]:
    return {
        "file": args.file,
        "goal": str(spec.goal),
        "implicit": True,
        "perspective": args.perspective,
    }


def _indent(text: str) -> str:
    return "\n".join("  " + line for line in text.splitlines())
