"""``epistemica show``: a spec's model, after some of its actions, as text, DOT or JSON.

Helper of :mod:`epistemica.cli`, imported only when the command runs. The model is the
explicit one (a Kripke model); ``--after`` applies the spec's actions one after the other
by product update, without contracting the result, so every world of ``M ⊗ A`` is shown.
"""

from __future__ import annotations

import argparse
import json

from epistemica.cli_coordination import split_plan
from epistemica.cli_exit import EXIT_OK
from epistemica.cli_inputs import load_input
from epistemica.del_ import KripkeModel, Spec, describe_model, to_dot
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.spec import names_hint
from epistemica.model_json import model_from_json, model_to_json

__all__ = ["model_after", "run_show"]


def model_after(spec: Spec, steps: list[str]) -> KripkeModel:
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
    spec, _task = load_input(args)
    steps = split_plan(args.after) if args.after.strip() else []
    model = model_after(spec, steps)
    # The atoms in the order the spec declares them (a model of explicit worlds may hold
    # them in another), the worlds by their spec names: the JSON form has both, and the
    # model read back from it is what the text and DOT outputs show.
    data = model_to_json(model, spec.atoms)
    if args.json:
        print(json.dumps({"file": args.file, "after": steps, **data}, indent=2))
    elif args.dot:
        text = to_dot(model_from_json(data))
        with open(args.dot, "w", encoding="utf-8") as out:
            out.write(text + "\n")
        print(f"wrote {args.dot}: {model.n_worlds} worlds, agents {', '.join(model.agents)}")
    else:
        print(f"{args.file}" + (f" after {', '.join(steps)}" if steps else ""))
        print(describe_model(model_from_json(data)))
    return EXIT_OK
