"""Writing a spec in SMCDEL's text format (``epistemica export --smcdel``).

An explicit model is written as SMCDEL states one: ``VARS``, a ``LAW`` whose satisfying
valuations are the worlds, ``OBS`` (each agent's observed atoms, read off its relation),
and one ``TRUE?`` or ``VALID?`` job per claim. A knowledge structure (a spec loaded on the
symbolic backend, or a model whose worlds are too many to list) is written from its own
parts: its variables, its law BDD as a disjunction of disjoint cubes and each agent's
observables, without listing a world. :mod:`epistemica.del_.formats.smcdel` reads the
format back.
"""

from __future__ import annotations

import re

import numpy as np

from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.del_.language.formula import (
    And,
    Atom,
    Bottom,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    Top,
)
from epistemica.del_.language.modalities import (
    After,
    Announce,
    AnnounceDiamond,
    Believe,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
)
from epistemica.del_.models import KnowledgeStructure
from epistemica.del_.spec import Spec
from epistemica.del_.symbolic.describe import cube_literals
from epistemica.del_.symbolic.relations import Observes

__all__ = ["KEYWORDS", "MAX_LAW_CUBES", "to_smcdel"]

#: A structure's law is written as a disjunction of disjoint cubes of its BDD; a law that
#: needs more is refused (SMCDEL's format has no shared subformulas).
MAX_LAW_CUBES = 200_000

#: SMCDEL's reserved words: no agent may be named like one.
KEYWORDS = {"VARS", "LAW", "OBS", "Top", "Bot", "Not", "not", "iff", "AND", "OR", "XOR",
             "ONEOF", "ForAll", "Forall", "Exists", "K", "Kw"}  # fmt: skip


def to_smcdel(spec: Spec) -> str:
    """SMCDEL's text for an S5 spec: VARS, LAW, OBS and one job per claim.

    Raises
    ------
    InvalidArgumentError
        The model is not a knowledge structure SMCDEL can state (a relation that is not
        "agree on some atoms", two worlds with one valuation), or a claim uses what
        SMCDEL's formulas cannot say (belief that is not knowledge, ``[ACT]`` for an action
        that is not a public announcement).
    """
    model = spec.model
    if isinstance(model, KnowledgeStructure):  # never listed: any size the BDDs hold
        return _structure_text(spec, model)
    if model.has_separate_knowledge():
        raise InvalidArgumentError(
            "the model has separate knowledge relations", hint="SMCDEL's structures are S5"
        )
    val = model.valuation
    if len({row.tobytes() for row in val}) != model.n_worlds:
        model = model.minimize()
        val = model.valuation
        if len({row.tobytes() for row in val}) != model.n_worlds:
            raise InvalidArgumentError(
                "two worlds of the model have one valuation",
                hint="SMCDEL's states are valuations; add an atom that tells them apart",
            )
    atoms = list(spec.atoms)
    column = [model.atoms.index(a) if a in model.atoms else None for a in atoms]
    rows = np.zeros((model.n_worlds, len(atoms)), dtype=bool)
    for j, c in enumerate(column):
        if c is not None:  # an atom of the spec that no world makes true stays false
            rows[:, j] = val[:, c]
    number = {a: k for k, a in enumerate(atoms, start=1)}
    agents = _agent_names(model.agents)
    lines = ["-- written by epistemica from " + spec.filename]
    lines += [f"-- epistemica atom {number[a]}: {a}" for a in atoms]
    lines += [f"-- epistemica agent {agents[a]}: {a}" for a in model.agents if agents[a] != a]
    law = _law(rows, 0, [number[a] for a in atoms], tuple(range(len(rows))))
    observed = {a: [number[atoms[j]] for j in _observed(model, a, rows)] for a in model.agents}
    numbers = [number[a] for a in atoms]
    _structure_lines(lines, numbers, law, observed, agents)
    writer = _FormulaWriter(number, agents, spec.actions)
    points = model.designated_positions
    for check in spec.checks:
        text = _claim_text(spec, check, writer)
        if len(points) == model.n_worlds:
            lines.append(f"VALID? {text}")
        elif len(points) == 1:
            true = [str(number[a]) for a, v in zip(atoms, rows[points[0]], strict=True) if v]
            true += [str(n) for n in numbers[len(atoms) :]]  # the constant atom, if any
            lines.append(f"TRUE? {{{','.join(true)}}} {text}")
        else:
            where = _law(rows[points], 0, [number[a] for a in atoms], tuple(range(len(points))))
            lines.append(f"VALID? ({where}) -> ({text})")
    return "\n".join(lines) + "\n"


def _agent_names(agents) -> dict[str, str]:
    out: dict[str, str] = {}
    for k, a in enumerate(agents, start=1):
        ok = re.fullmatch(r"[a-zA-Z][a-zA-Z0-9]*", a) and a not in KEYWORDS
        out[a] = a if ok else f"agent{k}"
    return out


def _observed(model, agent: str, rows: np.ndarray) -> list[int]:
    relation = model.belief_relations[agent]
    if not relation.is_equivalence():
        raise InvalidArgumentError(
            f"the relation of '{agent}' is not an equivalence", hint="SMCDEL's structures are S5"
        )
    sources, targets = relation.edges()
    same = (rows[sources] == rows[targets]).all(axis=0)
    seen = [j for j in range(rows.shape[1]) if same[j]]
    # The relation is within "agree on seen"; it is that relation iff it has as many edges.
    _, counts = np.unique(rows[:, seen], axis=0, return_counts=True)
    if int((counts.astype(np.int64) ** 2).sum()) != len(sources):
        raise InvalidArgumentError(
            f"'{agent}' tells apart worlds that agree on every atom it observes",
            hint="SMCDEL's agents observe atoms; add atoms for what the agent tells apart",
        )
    return seen


def _law(rows: np.ndarray, j: int, numbers: list[int], keep: tuple[int, ...]) -> str:
    """A formula true exactly at the valuations ``rows[keep]`` (Shannon expansion)."""
    n = len(numbers)
    if not keep:
        return "Bot"
    if len(keep) == 1 << (n - j):
        return "Top"
    pos = tuple(i for i in keep if rows[i, j])
    neg = tuple(i for i in keep if not rows[i, j])
    parts = []
    if pos:
        parts.append(f"({numbers[j]} & {_law(rows, j + 1, numbers, pos)})")
    if neg:
        parts.append(f"(~{numbers[j]} & {_law(rows, j + 1, numbers, neg)})")
    return parts[0] if len(parts) == 1 else f"({parts[0]} | {parts[1]})"


class _FormulaWriter:
    def __init__(self, number: dict[str, int], agents: dict[str, str], actions) -> None:
        self.number, self.agents, self.actions = number, agents, actions

    def write(self, f: Formula) -> str:
        w = self.write
        if isinstance(f, Top):
            return "Top"
        if isinstance(f, Bottom):
            return "Bot"
        if isinstance(f, Atom):
            return str(self.number[f.key])
        if isinstance(f, Not):
            return f"~ ({w(f.operand)})"
        if isinstance(f, (And, Or)) and isinstance(f.left, type(f)):
            # A long chain as one list (AND (...)), not nested pairs as deep as it is long.
            word = "AND" if isinstance(f, And) else "OR"
            return f"{word} (" + ", ".join(w(g) for g in _chain(f)) + ")"
        if isinstance(f, (And, Or, Implies, Iff)):
            op = {And: "&", Or: "|", Implies: "->", Iff: "iff"}[type(f)]
            return f"(({w(f.left)}) {op} ({w(f.right)}))"
        if isinstance(f, (Know, Believe)):
            return f"({self.agents[f.agent]} knows that ({w(f.operand)}))"
        if isinstance(f, KnowWhether):
            return f"({self.agents[f.agent]} knows whether ({w(f.operand)}))"
        if isinstance(f, (Everybody, EverybodyBelieves)):
            return "AND (" + ", ".join(w(Know(a, f.operand)) for a in f.group) + ")"
        if isinstance(f, (Common, CommonBelief, Distributed)):
            word = "distknow" if isinstance(f, Distributed) else "comknow"
            group = ",".join(self.agents[a] for a in f.group)
            return f"(({group}) {word} that ({w(f.operand)}))"
        if isinstance(f, Announce):
            return f"([ ! ({w(f.announcement)}) ] ({w(f.operand)}))"
        if isinstance(f, AnnounceDiamond):
            return f"(< ! ({w(f.announcement)}) > ({w(f.operand)}))"
        if isinstance(f, After):
            return self.after(f)
        raise InvalidArgumentError(f"SMCDEL has no formula for {type(f).__name__}")

    def after(self, f: After) -> str:
        action = self.actions.get(f.action)
        public = (
            action is not None
            and len(action.events) == 1
            and not action.post[0]
            and all(edges == ((0, 0, None),) for edges in action.edges.values())
            and action.knowledge_edges == action.edges
        )
        if not public:
            raise InvalidArgumentError(
                f"[{f.action}] is not a public announcement",
                hint="SMCDEL's text format has announcements [ ! f ] only",
            )
        return f"([ ! ({self.write(action.pre[0])}) ] ({self.write(f.operand)}))"


def _chain(f: And | Or) -> list[Formula]:
    """The operands of a chain of one connective, left to right, found without recursion."""
    parts, stack = [], [f]
    while stack:
        g = stack.pop()
        if type(g) is type(f):
            stack += [g.right, g.left]
        else:
            parts.append(g)
    return parts


def _structure_lines(lines: list, numbers: list, law: str, observed: dict, agents: dict) -> None:
    """Append VARS, LAW and OBS. SMCDEL's OBS lists at least one atom: who sees nothing
    sees a constant atom (always true), added to ``numbers``."""
    if not all(observed.values()):
        pad = max(numbers, default=0) + 1
        lines.append(f"-- epistemica constant {pad}: always true, observed by who sees nothing")
        numbers.append(pad)
        law = f"({law}) & {pad}"
        observed = {a: seen or [pad] for a, seen in observed.items()}
    lines.append("VARS " + ",".join(map(str, numbers)))
    lines.append("LAW  " + law)
    obs = [f"{agents[a]}: {','.join(map(str, seen))}" for a, seen in observed.items()]
    lines.append("OBS  " + "\n     ".join(obs))


def _claim_text(spec: Spec, check, writer: _FormulaWriter) -> str:
    """A claim as an SMCDEL formula that is valid where the claim is as expected."""
    try:
        text = writer.write(check.formula)
    except InvalidArgumentError as exc:
        raise SpecError(f"claim \"{check.name}\": {exc.message}", line=check.line,
                        column=check.column, source=spec.source, filename=spec.filename,
                        hint=exc.hint) from None  # fmt: skip
    return text if check.expected else f"~ ({text})"


def _structure_text(spec: Spec, s: KnowledgeStructure) -> str:
    """SMCDEL's text for a knowledge structure, from its variables, law and observables."""
    if s.has_separate_knowledge():
        raise InvalidArgumentError(
            "the structure has separate knowledge relations", hint="SMCDEL's structures are S5"
        )
    atoms = list(spec.atoms)
    number = {a: k for k, a in enumerate(atoms, start=1)}
    slot_of = s.atom_slots
    numbered = {slot_of[a]: number[a] for a in atoms if a in slot_of}
    hidden = [slot for slot in s.slots if slot not in numbered]
    numbered.update({slot: len(atoms) + k for k, slot in enumerate(hidden, start=1)})
    agents = _agent_names(s.agents)
    observed = {}
    for a in s.agents:
        relation = s.relation(a, "knowledge")
        if not isinstance(relation, Observes):
            raise InvalidArgumentError(
                f"'{a}' does not observe variables", hint="SMCDEL's agents observe atoms"
            )
        observed[a] = sorted(numbered[slot] for slot in relation.slots)
    numbers = sorted(numbered.values())
    lines = ["-- written by epistemica from " + spec.filename]
    lines += [f"-- epistemica atom {number[a]}: {a}" for a in atoms]
    lines += [f"-- epistemica agent {agents[a]}: {a}" for a in s.agents if agents[a] != a]
    law = _cubes_text(s.law, numbered)
    _structure_lines(lines, numbers, law, observed, agents)
    everywhere = not (s.law & ~s.designated_states).satisfiable()
    where = None if everywhere else _cubes_text(s.designated_states & s.law, numbered)
    writer = _FormulaWriter(number, agents, spec.actions)
    for check in spec.checks:
        text = _claim_text(spec, check, writer)
        lines.append(f"VALID? {text}" if where is None else f"VALID? ({where}) -> ({text})")
    return "\n".join(lines) + "\n"


def _cubes_text(f, numbered: dict[int, int]) -> str:
    """``f`` (a BDD over the structure's variables) as a disjunction of disjoint cubes."""
    slots = sorted(numbered, key=numbered.get)
    terms = [
        "AND (" + ", ".join(str(numbered[slot]) if value else f"~{numbered[slot]}"
                            for slot, value in cube) + ")" if cube else "Top"
        for cube in cube_literals(f, slots, MAX_LAW_CUBES)
    ]  # fmt: skip
    return "OR (" + ", ".join(terms) + ")" if terms else "Bot"
