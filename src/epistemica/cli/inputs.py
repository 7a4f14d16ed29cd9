"""Reading what ``check``, ``plan`` and ``show`` are given: a spec, an EPDDL task, SMCDEL.

Helper of the command modules (imported when one of them runs). See
:mod:`epistemica.cli.formats` for the arguments.
"""

from __future__ import annotations

import argparse
import importlib
from typing import TYPE_CHECKING, Any

from epistemica.cli.plan_steps import split_plan
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.formats.kinds import is_epddl, is_smcdel
from epistemica.del_.spec import Spec, parse_spec
from epistemica.input_files import read_input

if TYPE_CHECKING:
    from epistemica.del_.formats.epddl import EpddlTask
    from epistemica.del_.formats.smcdel import SmcdelFile

__all__ = ["READERS", "is_foreign", "load_input", "plank_line", "where_lines"]

#: The readers of foreign formats, loaded by name when an input is in that format (their
#: grammars and compilers cost a ``.epi`` check most of its start-up otherwise).
READERS = {
    "epddl": "epistemica.del_.formats.epddl:load_epddl",
    "smcdel": "epistemica.del_.formats.smcdel:load_smcdel",
}


def _reader(kind: str) -> Any:
    module, _, name = READERS[kind].partition(":")
    return getattr(importlib.import_module(module), name)


def load_input(
    args: argparse.Namespace, backend: str = "explicit", command: str = "check", text=None
) -> tuple[Spec, Any]:
    """The spec named on the command line, and where it came from: the :class:`EpddlTask`
    of an EPDDL input, the :class:`SmcdelFile` of an SMCDEL one, ``None`` for a spec.

    ``args.file`` (with ``args.problem`` and ``args.library``) names a ``.epi`` spec, an
    EPDDL domain and problem, or an SMCDEL file. Plank's names of ground actions in
    ``--verify`` and ``--after`` are translated to epistemica's. A spec is read once,
    bounded (:func:`epistemica.input_files.read_input`), unless its ``text`` is given.
    """
    problem = getattr(args, "problem", None)
    libraries = getattr(args, "library", None) or []
    if problem is not None or is_epddl(args.file):
        if problem is None:
            raise InvalidArgumentError(
                f"{args.file} is EPDDL: give the domain and the problem",
                hint="epistemica plan DOMAIN.epddl PROBLEM.epddl [-l LIBRARY.epddl]",
            )
        task = _reader("epddl")(args.file, problem, libraries)
        _translate(args, task.plank_names)
        return task.spec, task
    if libraries:
        raise InvalidArgumentError(
            "-l/--library applies to EPDDL tasks", hint="give a domain and a problem (.epddl)"
        )
    if is_smcdel(args.file):
        found = _reader("smcdel")(args.file, backend)
        return found.spec, found
    if text is None:
        text = read_input(args.file, command)[1]
    return parse_spec(text, args.file, backend), None


def is_foreign(args: argparse.Namespace) -> bool:
    """Whether the command line names an EPDDL task or an SMCDEL file."""
    return getattr(args, "problem", None) is not None or is_epddl(args.file) or is_smcdel(args.file)


def plank_line(task: EpddlTask, plan: list[str]) -> str:
    """The plan as plank's ``validate`` takes it (``-a`` followed by the actions)."""
    return "plank validate ... -a " + " ".join(task.plank_plan(plan))


def where_lines(found: SmcdelFile) -> list[str]:
    """SMCDEL's ``WHERE?`` answers: per query, the states (true atoms) where it holds."""
    spec = found.spec
    lines = []
    for text, formula in found.where:
        model = spec.model
        if hasattr(model, "truth_mask"):
            mask = model.truth_mask(formula, actions=spec.actions)
            states = [sorted(model.valuation_of(w)) for w in model.worlds_at(mask.nonzero()[0])]
            shown = "; ".join("{" + ", ".join(s) + "}" for s in states[:12])
            more = f"; ... and {len(states) - 12} more" if len(states) > 12 else ""
            lines.append(f"  {text}\n    {len(states)} of {model.n_worlds} states: {shown}{more}")
        else:
            n = model.count(formula, spec.actions)
            lines.append(f"  {text}\n    {n} of {model.n_worlds} states (symbolic backend)")
    return lines


def _translate(args: argparse.Namespace, plank_names: dict[str, str]) -> None:
    ours = {plank: key for key, plank in plank_names.items()}
    for field in ("verify", "after"):
        text = getattr(args, field, None)
        if text and text.strip():
            steps = [ours.get(step, step) for step in split_plan(text)]
            setattr(args, field, ",".join(steps))
