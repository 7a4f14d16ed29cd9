"""``epistemica show``: a spec's model, after some of its actions, as text, DOT or JSON.

Helper of :mod:`epistemica.cli`, imported only when the command runs. ``--after``
applies the spec's actions one after the other by product update, without contracting
the result, so every world of ``M ⊗ A`` is shown. On the explicit backend the worlds and
relations are listed (``--limit N``: the designated and first worlds, N in all); on the
symbolic one the knowledge structure is shown as SMCDEL prints one (vocabulary, law,
observables). Every output is linear in the size of the model.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from epistemica.cli.exit import EXIT_OK
from epistemica.cli.inputs import load_input
from epistemica.cli.plan_steps import split_plan
from epistemica.del_ import KnowledgeStructure, KripkeModel, Spec, describe_model, to_dot
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.spec import names_hint
from epistemica.del_.symbolic.describe import describe_structure, structure_to_json
from epistemica.model_json import dumps, model_to_json
from epistemica.model_view import write_model_view
from epistemica.output_files import check_output, write_output

__all__ = ["model_after", "run_show"]


def model_after(spec: Spec, steps: list[str]) -> KripkeModel | KnowledgeStructure:
    """The spec's model after the actions ``steps``, in order (product update).

    Raises
    ------
    InvalidArgumentError
        An action the spec does not declare, or one that cannot happen at that point.
    """
    model = spec.model
    for i, name in enumerate(steps, start=1):
        if name not in spec.actions:
            raise InvalidArgumentError(
                f"--after names an unknown action '{name}'",
                hint=names_hint(name, spec.actions, "action"),
            )
        action = spec.actions[name]
        if not model.applicable_in_some(action):
            done = f"after {', '.join(steps[: i - 1])}" if i > 1 else "in the initial model"
            raise InvalidArgumentError(
                f"action {i} ({name}) cannot happen {done}: no designated event's "
                "precondition holds at a designated world",
                hint="check the order of the actions, or 'epistemica show' the model before it",
            )
        model = model.update(action)
    return model


def run_show(args: argparse.Namespace) -> int:
    """Run ``epistemica show`` with parsed arguments; return the exit status."""
    inputs = [args.file, getattr(args, "problem", None), *getattr(args, "library", [])]
    for flag in ("html", "dot"):
        if getattr(args, flag, None):  # before any work: never over an input or unasked
            check_output(getattr(args, flag), inputs, args.force, f"--{flag}")
    spec, _task = load_input(args, args.backend, "show")
    steps = split_plan(args.after) if args.after.strip() else []
    model = model_after(spec, steps)
    title = f"{args.file}" + (f" after {', '.join(steps)}" if steps else "")
    if isinstance(model, KnowledgeStructure):
        if getattr(args, "html", None):
            raise InvalidArgumentError(
                "--html shows explicit models only", hint="add --backend explicit"
            )
        return _show_structure(model, args, steps, title)
    limit = args.limit
    if args.json:
        # The atoms in the order the spec declares them, the worlds by their spec names.
        data = model_to_json(model, spec.atoms, limit)
        print(dumps({"file": args.file, "after": steps, **data}))
    elif getattr(args, "html", None):
        write_model_view(spec, model, args.html, title, limit)
        print(f"wrote {args.html}: {model.n_worlds} worlds; open it in a browser")
    elif args.dot:
        shown = _first_worlds(model, limit)
        write_output(args.dot, to_dot(shown) + "\n")
        part = f" (the first {shown.n_worlds})" if shown is not model else ""
        print(f"wrote {args.dot}: {model.n_worlds} worlds{part}, agents {', '.join(model.agents)}")
    else:
        print(title)
        print(describe_model(model, max_worlds=limit or _TEXT_WORLDS))
    return EXIT_OK


_TEXT_WORLDS = 16


def _first_worlds(model: KripkeModel, limit: int | None) -> KripkeModel:
    """The designated worlds and then the first ones, ``limit`` in all (for DOT)."""
    if limit is None or model.n_worlds <= limit:
        return model
    keep = np.zeros(model.n_worlds, dtype=bool)
    keep[model.designated_positions[:limit]] = True
    spare = limit - int(keep.sum())
    keep[np.flatnonzero(~keep)[: max(spare, 0)]] = True
    kept = model.designated_positions[keep[model.designated_positions]]
    return model.restricted(keep, np.cumsum(keep)[kept] - 1)


def _show_structure(s: KnowledgeStructure, args: argparse.Namespace, steps, title: str) -> int:
    if args.dot:
        raise InvalidArgumentError(
            "--dot draws worlds, and this spec is on the symbolic backend (a knowledge "
            "structure lists none)",
            hint="use --json or the text output; --backend explicit for a small model",
        )
    if args.json:
        data = structure_to_json(s, args.limit or _JSON_STATES)
        print(json.dumps({"file": args.file, "after": steps, **data}, indent=2))
    else:
        print(title)
        print(describe_structure(s, args.limit or _TEXT_WORLDS))
    return EXIT_OK


_JSON_STATES = 1000
