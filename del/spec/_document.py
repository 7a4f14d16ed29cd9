"""Spec files (``.epi``): an initial Kripke model, actions, a goal and checked claims.

The grammar is ``spec.lark``, which imports the formula rules of ``formula.lark``; this
module is the public entry point and compiles a text in three stages:
:mod:`~epistemica.del_.spec._syntax` parses it (located syntax errors),
:mod:`~epistemica.del_.spec._compiler` compiles the declarations, goal and claims, with
:mod:`~epistemica.del_.spec._names` (ranges, parameters, action schemas),
:mod:`~epistemica.del_.spec._model` (the initial model) and
:mod:`~epistemica.del_.spec._actions` (the actions and their owners).

Every meaningful mistake (an unknown agent or atom, a name declared twice, a law nothing
satisfies, an unbound parameter, ...) raises :class:`~epistemica.del_.errors.SpecError`
pointing at the offending token of the file, with a hint; malformed text raises
:class:`~epistemica.del_.errors.ParseError`.
See ``docs/language.md``, section "Spec files", for the language.

Examples
--------
>>> spec = parse_spec('''
... agents a, b
... atoms heads
... actual {heads}
... action show: sense heads by b
... check "b learns the coin": [show] (Kw[b] heads & ~Kw[a] heads & K[a] Kw[b] heads)
... ''')
>>> spec.model.n_worlds, sorted(spec.actions)
(2, ['show'])
>>> [(c.name, c.expected, spec.holds(c.formula)) for c in spec.checks]
[('b learns the coin', True, True)]
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from epistemica.del_.errors import ParseError, SpecError
from epistemica.del_.language.formula import Formula
from epistemica.del_.models import KripkeModel
from epistemica.del_.spec._compiler import Check, Compiler, Names, compile_formula
from epistemica.del_.spec._fast_syntax import FastPathMiss
from epistemica.del_.spec._plausibility import resolve_upgrades
from epistemica.del_.spec._source import check_claim_count, check_token_count, read_source
from epistemica.del_.spec._syntax import parse
from epistemica.del_.spec.backend import check_backend, model_builder, on_backend

__all__ = ["Check", "Spec", "load_spec", "parse_spec"]


@dataclass(frozen=True, eq=False)
class Spec:
    """A compiled spec file.

    Attributes
    ----------
    model : KripkeModel
        The initial model (a :class:`~epistemica.del_.KnowledgeStructure` when
        loaded for the symbolic backend).
    actions : dict
        Action name -> :class:`~epistemica.del_.explicit.action.ActionModel`; a parametrised schema
        contributes one entry per binding, named like ``open(a)``.
    goal : Formula or None
    checks : tuple of Check
    agents, atoms : tuple of str
        In declaration order (atoms canonical, as in ``at(r1, g1)``).
    filename : str
    source : str
        The text of the spec.
    owners : dict
        Action name -> the agent that executes it, for the actions declared with
        ``by AGENT`` (used for implicit coordination).
    plausibility : PlausibilityModel, PlausibilityStructure or None
        The plausibility model of the ``plausibility`` lines (on the model's backend);
        when present, :meth:`holds` evaluates claims there.
    upgrades : dict
        Upgrade name -> (``"radical"`` or ``"conservative"``, its formula).
    """

    model: KripkeModel
    actions: dict[str, Any]
    goal: Formula | None
    checks: tuple[Check, ...]
    agents: tuple[str, ...]
    atoms: tuple[str, ...]
    filename: str
    source: str = field(repr=False)
    owners: dict[str, str] = field(default_factory=dict)
    plausibility: Any = None
    upgrades: dict[str, tuple[str, Formula]] = field(default_factory=dict)

    def __repr__(self) -> str:
        return (
            f"<Spec {self.filename}: {len(self.agents)} agents, {len(self.atoms)} atoms, "
            f"{self.model.n_worlds} worlds, {len(self.actions)} actions, {len(self.checks)} checks>"
        )

    def holds(self, formula: Formula | str) -> bool:
        """Whether ``formula`` holds at the designated worlds, resolving ``[ACT]`` here."""
        if isinstance(formula, str):
            formula = self.formula(formula)
        if self.plausibility is not None:
            return self.plausibility.holds(resolve_upgrades(formula, self.upgrades))
        return self.model.holds(formula, actions=self.actions)

    def require_goal(self) -> Formula:
        """The goal, or a :class:`SpecError` located at the end of the file if there is none.

        Examples
        --------
        >>> parse_spec("agents a\\natoms p\\n", "demo.epi").require_goal()
        Traceback (most recent call last):
        ...
        epistemica.del_.errors.SpecError: demo.epi:3:1: error: the spec has no goal
        hint: add a line such as 'goal K[a] p' to plan for
        """
        if self.goal is not None:
            return self.goal
        line = self.source.count("\n") + 1  # where a goal line would be added
        column = len(self.source) - (self.source.rfind("\n") + 1) + 1
        agent = self.agents[0] if self.agents else "a"
        atom = self.atoms[0] if self.atoms else "p"
        raise SpecError(
            "the spec has no goal", line=line, column=column, source=self.source,
            filename=self.filename, hint=f"add a line such as 'goal K[{agent}] {atom}' to plan for",
        )  # fmt: skip

    def formula(self, text: str, filename: str = "<formula>") -> Formula:
        """Parse ``text`` as a formula over this spec's agents, atoms and actions.

        Raises
        ------
        ParseError, SpecError
            Located in ``text`` (e.g. an atom the spec does not declare).

        Examples
        --------
        >>> spec = parse_spec("agents a\\natoms p")
        >>> print(spec.formula("K[a] p | ~p"))
        K[a] p | ~p
        >>> spec.formula("K[a] q")
        Traceback (most recent call last):
        ...
        epistemica.del_.errors.SpecError: <formula>:1:6: error: unknown atom 'q'
            K[a] q
                 ^
        hint: declared atoms: p
        """
        if not text.strip():
            raise ParseError(
                "empty formula", line=1, column=1, source=text, filename=filename,
                hint="write a formula such as 'K[a] p'",
            )  # fmt: skip
        names = Names(self.agents, self.atoms, frozenset(self.actions) | set(self.upgrades))
        return compile_formula(text, filename, names)


def parse_spec(text: str, filename: str = "<string>", backend: str = "auto") -> Spec:
    """Compile the text of a spec file.

    Parameters
    ----------
    text : str
        The spec, in the language of ``docs/language.md``.
    filename : str
        Shown in error messages.
    backend : {"auto", "explicit", "symbolic"}
        The model's backend (see :mod:`epistemica.del_.spec.backend`): ``"auto"`` gives a
        :class:`~epistemica.del_.KripkeModel` unless the spec is too large to enumerate
        (an ``observes`` spec of more than 20 atoms, or more than 2^20 worlds), then a
        :class:`~epistemica.del_.KnowledgeStructure`; ``"explicit"`` and ``"symbolic"``
        force one.

    Raises
    ------
    ParseError
        The text does not follow the grammar.
    SpecError
        It parses but is not meaningful; the error names the offending token.

    Examples
    --------
    >>> spec = parse_spec('''
    ... agents c1, c2
    ... atoms m1..m2
    ... observes c1: m2
    ... observes c2: m1
    ... actual {m1, m2}
    ... ''')
    >>> spec.holds("~Kw[c1] m1 & K[c1] m2")
    True
    >>> type(parse_spec("agents a\\natoms m1..m30\\nobserves a: m1").model).__name__
    'KnowledgeStructure'
    >>> parse_spec("agents a\\natoms p\\ngoal K[b] p")
    Traceback (most recent call last):
    ...
    epistemica.del_.errors.SpecError: <string>:3:8: error: unknown agent 'b'
        goal K[b] p
               ^
    hint: declared agents: a
    """
    check_token_count(text, filename)  # before parsing: every token costs memory
    check_claim_count(text, filename)
    build = model_builder(backend)
    try:
        parts = Compiler(text, filename, observables=build).compile(parse(text, filename, "start"))
    except FastPathMiss:  # a name the fast path cannot locate: lark's tree, lark's errors
        tree = parse(text, filename, "start", fast=False)
        parts = Compiler(text, filename, observables=build).compile(tree)
    declared = parts.plausibility
    spec = Spec(**parts._asdict(), filename=filename, source=text)
    model = on_backend(spec.model, spec.atoms, backend)
    if declared is not None:
        plausibility = declared.build(symbolic=not isinstance(model, KripkeModel))
        return dataclasses.replace(spec, model=model, plausibility=plausibility)
    return spec if model is spec.model else dataclasses.replace(spec, model=model)


def load_spec(path: str | Path, backend: str = "auto") -> Spec:
    """Read and compile a spec file: the one loader of the API and the command line.

    The file is read once (a pipe works), at most
    :data:`~epistemica.del_.spec._source.MAX_SOURCE_BYTES` bytes, as UTF-8 (a byte-order
    mark is dropped). ``backend``: see :func:`parse_spec`.

    Raises
    ------
    SourceError
        The file cannot be read, is too large, binary or not UTF-8 (see
        :func:`~epistemica.del_.spec._source.read_source`).
    ParseError, SpecError
        See :func:`parse_spec`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> text = "agents " + ", ".join(f"c{i}" for i in range(30)) + "\\natoms m0..m29\\n"
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "big.epi"
    >>> _ = path.write_text(text)
    >>> type(load_spec(path).model).__name__
    'KnowledgeStructure'
    >>> load_spec(path, "symbolic").holds("~Kw[c1] m1")
    True
    """
    check_backend(backend)
    return parse_spec(read_source(path, "spec file"), filename=str(path), backend=backend)
