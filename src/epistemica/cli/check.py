"""``epistemica check``: the claims of a spec file, or one formula (``--formula``).

Helper of :mod:`epistemica.cli`, imported only when the command runs. Exit status 0 when
every claim is as expected, 1 otherwise; ``--formula`` is a question (exit 0 whatever the
answer) unless ``--expect true|false`` makes it a claim.
"""

from __future__ import annotations

import argparse
import importlib
import itertools
from typing import Any

import numpy as np

from epistemica.cli.exit import EXIT_FALSE, EXIT_OK
from epistemica.cli.inputs import is_foreign, load_input, where_lines
from epistemica.cli.json_output import print_json
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.describe import world_label, world_labels
from epistemica.del_.spec.backend import formula_summary
from epistemica.del_.symbolic.describe import iter_valuations
from epistemica.input_files import read_input

__all__ = ["COMMANDS", "run_check"]

#: Checking a mission file: loaded by name when the file is one.
COMMANDS = {"mission": "epistemica.cli.run:check_mission"}

# Worlds listed by `check --formula` before "... and N more" (text) / truncation (JSON).
_LIST_TEXT, _LIST_JSON = 12, 1000
_WHERE = 100  # worlds listed by --where without --limit
# Up to this many worlds every label is made, so that clashes fall back to w<index>.
_LABEL_ALL = 100_000


def _world(model: Any, world: Any, label) -> dict[str, Any]:
    true = model.valuation_of(world)
    return {"world": label(world), "atoms": [a for a in model.atoms if a in true]}


def _count(n: int) -> str:
    """A number of worlds for a line of text: 2^400 is not printed digit by digit."""
    if n < 10**12:
        return f"{n:,}"
    if n & (n - 1) == 0:
        return f"2^{n.bit_length() - 1}"
    return f"about 2^{n.bit_length() - 1}"


def _listing(names, shown: int = 10) -> str:
    names = list(names)
    if len(names) <= shown:
        return ", ".join(names)
    return ", ".join(names[:shown]) + f", ... ({len(names)} in all)"


def _show(entry: dict[str, Any]) -> str:
    return f"{entry['world']} {{{', '.join(entry['atoms'])}}}"


def run_check(args: argparse.Namespace) -> int:

    text = None
    if not is_foreign(args):
        kind, text = read_input(args.file, "check", ("spec", "mission"))
        if kind == "mission":  # the simulator's modules load only for a mission file
            module, _, name = COMMANDS["mission"].partition(":")
            return getattr(importlib.import_module(module), name)(args, text)
    if args.after is not None or args.robot is not None:
        raise InvalidArgumentError(
            "--after and --robot apply to mission files", hint="a file starting with 'mission'"
        )
    spec, source = load_input(args, args.backend, "check", text)
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
        print_json("check", {**out, "failed": len(failed)})
        return EXIT_FALSE if failed else EXIT_OK
    model = spec.model
    print(
        f"{args.file}: {len(results)} claim{'s' if len(results) != 1 else ''}; "
        f"{_count(model.n_worlds)} worlds, agents {_listing(spec.agents)}"
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
    if getattr(source, "where", None):
        print("WHERE?")
        print("\n".join(where_lines(source)))
    return EXIT_FALSE if failed else EXIT_OK


def answer_status(holds: bool, args: argparse.Namespace) -> int:
    """The exit status of ``--formula``: a question (0 either way), or with ``--expect``
    a claim (1 when the answer differs)."""
    expected = getattr(args, "expect", None)
    if expected is None:
        return EXIT_OK
    return EXIT_OK if holds == (expected == "true") else EXIT_FALSE


def _check_formula(spec: Any, args: argparse.Namespace) -> int:
    formula = spec.formula(args.formula)
    text_cap, json_cap = _LIST_TEXT, _LIST_JSON
    if args.where:  # list the worlds, as SMCDEL's WHERE? does, up to --limit
        text_cap = json_cap = args.limit or _WHERE
    if spec.plausibility is not None:  # claims are about the plausibility model
        holds = spec.holds(formula)
        if args.json:
            document = {"file": args.file, "formula": str(formula), "holds": holds}
            print_json("check-formula", document)
        else:
            print(f"{formula}\n  {'true' if holds else 'false'} at the designated worlds")
        return answer_status(holds, args)
    model = spec.model
    if not hasattr(model, "truth_set"):  # a KnowledgeStructure: it lists no worlds
        return _check_formula_symbolic(spec, formula, args)
    # Name only the worlds printed: a model of 2^24 worlds has 16 million names.
    mask = model.truth_mask(formula, actions=spec.actions)
    true_positions = np.flatnonzero(mask)
    points = model.designated_positions
    if model.n_worlds <= _LABEL_ALL:
        every = world_labels(model)
        labels = every.__getitem__
    else:
        labels = world_label
    listed_points = points[:json_cap]
    designated = [
        {**_world(model, w, labels), "holds": bool(mask[p])}
        for p, w in zip(listed_points, model.worlds_at(listed_points), strict=True)
    ]
    holds = bool(mask[points].all())
    n_true = len(true_positions)
    true_worlds = model.worlds_at(true_positions[:json_cap])
    if args.json:
        listed = [_world(model, w, labels) for w in true_worlds[:json_cap]]
        print_json(
            "check-formula",
            {
                "file": args.file,
                "formula": str(formula),
                "holds": holds,
                "designated": designated,
                "n_worlds": model.n_worlds,
                "n_true": n_true,
                "worlds": listed,
                "truncated": n_true > len(listed),
            },
        )
        return answer_status(holds, args)
    print(f"{formula}")
    print(f"  {'true' if holds else 'false'} at the designated world", end="")
    if len(points) == 1:
        print(f" {_show(designated[0])}")
    else:
        n_ok = int(mask[points].sum())
        print(f"s: holds at {n_ok} of {len(points)}")
        for d in designated[:text_cap]:
            print(f"    {'true ' if d['holds'] else 'false'}  {_show(d)}")
    shown = ", ".join(_show(_world(model, w, labels)) for w in true_worlds[:text_cap])
    more = n_true - text_cap
    tail = f", ... and {more} more" if more > 0 else ""
    print(f"  holds at {n_true} of {model.n_worlds} worlds" + (":" if shown else ""))
    if shown:
        print(f"    {shown}{tail}")
    return answer_status(holds, args)


def _check_formula_symbolic(spec: Any, formula: Any, args: argparse.Namespace) -> int:
    """Counts, and with --where the valuations: a knowledge structure lists no worlds."""
    summary = formula_summary(spec, formula)
    listed: list[list[str]] = []
    if args.where:
        limit = args.limit or _WHERE
        truth = spec.model.truth(formula, spec.actions)
        listed = list(itertools.islice(iter_valuations(spec.model, truth), limit + 1))
        summary["truncated"] = len(listed) > limit
        summary["valuations"] = listed = listed[:limit]
    if args.json:
        print_json("check-formula", {"file": args.file, "formula": str(formula), **summary})
        return answer_status(summary["holds"], args)
    print(f"{formula}")
    print(
        f"  {'true' if summary['holds'] else 'false'} at the designated worlds: holds at "
        f"{summary['n_designated_true']} of {summary['n_designated']}"
    )
    print(f"  holds at {summary['n_true']} of {summary['n_worlds']} worlds (symbolic backend)")
    if args.where:
        more = " ..." if summary["truncated"] else ""
        print("  where (true atoms of each valuation):")
        print("    " + "  ".join("{" + ", ".join(v) + "}" for v in listed) + more)
    return answer_status(summary["holds"], args)
