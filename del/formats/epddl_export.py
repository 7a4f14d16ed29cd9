"""Writing a spec as EPDDL: a domain, a problem and an action-type library.

:func:`to_epddl` writes what a :class:`~epistemica.del_.spec.Spec` compiles into (initial
model, actions, goal) in EPDDL as plank reads it, so that another planner or plank's
validator can run it:

- the initial model as explicit worlds (``:worlds``, ``:relations``, ``:labels``,
  ``:designated``), each agent's relation edge by edge; a knowledge structure with more
  states than :data:`MAX_WORLDS` (or any, with ``theory=True``) as a finitary S5 theory,
  without listing a state: ``[C. All]`` of its law, ``[C. All] ([Kw. a] p)`` for each
  atom ``p`` agent ``a`` observes, and its designated states as a propositional formula
  (the law and the designated states as disjunctions of disjoint cubes of their BDDs);
- each action as an action type of its own in the library (its events, one observability
  type per distinct relation, its designated events), the domain's events (precondition;
  ``p := f`` as ``(iff f (p))``) and an action without parameters whose agents have
  static observability types. An edge condition ``if F`` (evaluated where the action
  happens) becomes events of their own: each event is split by the truth of the action's
  conditions, so the event model has no conditions and the same product update;
- atoms ``at(r1, g1)`` as predicates over ``entity`` (the arguments are objects or agents);
- formulas with ``[a]`` for ``B[a]`` (EPDDL agents have one relation), ``[Kw. a]``,
  ``[(a b)]`` for ``EB``, ``[C. (a b)]`` for ``CB``.

A spec whose model or actions give an agent a separate knowledge relation is written with
its belief relations, which EPDDL's ``[a]`` reads; ``K``, ``Kw``, ``E`` and ``C`` are then
refused in the goal (they would read knowledge). ``D[G]``, announcements and ``[ACT]``
modalities have no EPDDL formula and are refused, as are claims (EPDDL has none: they are
not written).

Examples
--------
>>> from epistemica.del_.spec import parse_spec
>>> spec = parse_spec('''agents a, b
... atoms heads
... actual {heads}
... action show: sense heads by b
... goal Kw[b] heads & ~Kw[a] heads''')
>>> files = to_epddl(spec, "coin")
>>> sorted(files)
['domain', 'library', 'problem']
>>> print(files["problem"].splitlines()[-2])
  (:goal (and ([Kw. b] (heads)) (not ([Kw. a] (heads)))))
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Iterable
from functools import cached_property

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.language.formula import And, Atom, Bottom, Formula, Iff, Implies, Not, Or, Top
from epistemica.del_.language.modalities import (
    Believe,
    Common,
    CommonBelief,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
)
from epistemica.del_.language.parser import as_formula
from epistemica.del_.models import KnowledgeStructure
from epistemica.del_.spec import Spec
from epistemica.del_.symbolic.describe import cube_literals
from epistemica.del_.symbolic.relations import Observes

__all__ = ["MAX_CUBES", "MAX_PAIRS", "MAX_WORLDS", "atom_renaming", "to_epddl"]

#: Bound on the edges written for the initial model.
MAX_PAIRS = 2_000_000
#: Bound on the disjoint cubes written for a theory's law or designated states.
MAX_CUBES = 200_000

_KEYWORDS = {"and", "or", "not", "imply", "exists", "forall", "true", "false", "when", "iff",
             "if", "else", "else-if", "default", "All", "either", "define", "domain",
             "problem", "action-type-library", "basic", "entity", "object", "agent",
             "world", "event"}  # fmt: skip
_KNOWLEDGE = (Know, KnowWhether, Everybody, Common)
_REQUIREMENTS = (
    ":typing :lists :list-comprehensions :partial-observability :ontic-actions "
    ":conditional-effects :multi-pointed-models :group-modalities :knowing-whether "
    ":common-knowledge :general-preconditions :general-postconditions :general-goals "
    ":general-obs-conditions :negative-preconditions :negative-postconditions :negative-goals "
    ":modal-preconditions :modal-postconditions :modal-goals :disjunctive-preconditions "
    ":disjunctive-postconditions :disjunctive-goals :finitary-S5-theories"
)


def to_epddl(spec: Spec, name: str = "task", theory: bool | None = None) -> dict[str, str]:
    """The EPDDL texts of ``spec``: ``{"domain": ..., "problem": ..., "library": ...}``.

    ``theory`` chooses how a knowledge structure's initial state is written: ``None``
    lists its states up to :data:`MAX_WORLDS` and writes a finitary S5 theory above;
    ``True`` always writes the theory; ``False`` always lists (refused above the bound).
    A Kripke model is always listed.

    Raises
    ------
    InvalidArgumentError
        The spec uses what EPDDL cannot say (see the module docstring); the message names
        it.
    """
    if spec.plausibility is not None:
        raise InvalidArgumentError(
            "EPDDL has no plausibility orders: exporting this spec would drop its "
            "'plausibility' lines and change what its claims mean",
            hint="remove the plausibility and upgrade lines to export the hard part",
        )
    writer = _Writer(spec, _identifier(name, set()), theory)
    return {"domain": writer.domain(), "problem": writer.problem(), "library": writer.library()}


def atom_renaming(spec: Spec) -> dict[str, str]:
    """Each atom of ``spec`` -> the atom its EPDDL export reads back as.

    Names that are not EPDDL identifiers (arguments ``1``, EPDDL keywords) are renamed on
    export; the others come back unchanged.

    Examples
    --------
    >>> from epistemica.del_.spec import parse_spec
    >>> atom_renaming(parse_spec("agents a\\natoms box(1, 2), p"))
    {'box(1, 2)': 'box(x1, x2)', 'p': 'p'}
    """
    writer = _Writer(spec, "task")
    return {key: writer.atom_key(key) for key in spec.atoms}


def _identifier(text: str, taken: set[str]) -> str:
    """A fresh EPDDL identifier close to ``text``."""
    base = re.sub(r"[^A-Za-z0-9_-]+", "_", text).strip("_") or "x"
    if not (base[0].isalpha() or base[0] == "_"):
        base = "x" + base
    candidate, k = base, 1
    while candidate in taken or candidate in _KEYWORDS:
        k += 1
        candidate = f"{base}-{k}"
    taken.add(candidate)
    return candidate


#: A knowledge structure is listed (and then minimized) up to this many states, and
#: written as a finitary S5 theory above.
MAX_WORLDS = 1 << 20


def _initial(model, theory: bool | None):
    """The initial model as it is written: a Kripke model (listed), or a knowledge
    structure (written as a theory)."""
    if not isinstance(model, KnowledgeStructure):
        return model
    if theory is None:
        theory = model.n_worlds > MAX_WORLDS
    if theory:
        _check_theory(model)
        return model
    if model.n_worlds > MAX_WORLDS:
        raise InvalidArgumentError(
            f"listing the initial state's {model.n_worlds:,} states (more than "
            f"{MAX_WORLDS:,}) is too costly",
            hint="leave theory unset to write it as a finitary S5 theory",
        )
    return model.to_kripke(max_worlds=MAX_WORLDS)


def _check_theory(s: KnowledgeStructure) -> None:
    """A finitary S5 theory states a structure whose agents observe atoms, one
    relation each, and whose variables are all atoms."""
    if s.has_separate_knowledge():
        raise InvalidArgumentError(
            "a finitary S5 theory gives each agent one relation, and this structure has "
            "separate knowledge relations",
            hint="export --smcdel, or list the states (a smaller instance)",
        )
    for agent in s.agents:
        if not isinstance(s.relation(agent, "knowledge"), Observes):
            raise InvalidArgumentError(
                f"'{agent}' does not observe atoms, so no finitary S5 theory states its "
                "relation", hint="list the states (a smaller instance)",
            )  # fmt: skip
    if len(s.slots) != len(s.atom_slots):
        raise InvalidArgumentError(
            "the structure has variables that are not atoms, which a theory cannot name",
            hint="list the states (a smaller instance)",
        )


class _Writer:
    def __init__(self, spec: Spec, name: str, theory: bool | None = None) -> None:
        self.spec = spec
        self.name = name
        self.model = _initial(spec.model, theory)
        separate = self.model.has_separate_knowledge() or any(
            a.knowledge_edges != a.edges for a in spec.actions.values()
        )
        if spec.goal is not None and separate:
            for g in spec.goal.subformulas():
                if isinstance(g, _KNOWLEDGE):
                    raise InvalidArgumentError(
                        f"the goal uses knowledge ({g}) in a spec with separate knowledge "
                        "relations; EPDDL agents have one relation",
                        hint="write the goal with B, EB and CB (what EPDDL's [a] reads)",
                    )
        taken: set[str] = set()
        self.agents = {a: _identifier(a, taken) for a in self.model.agents}
        stems: dict[str, int] = {}
        self.args: dict[str, str] = {}
        for key in spec.atoms:
            atom = _parse_atom(key)
            if stems.setdefault(atom.name, len(atom.args)) != len(atom.args):
                raise InvalidArgumentError(
                    f"atoms '{atom.name}' with different numbers of arguments",
                    hint="EPDDL predicates have one arity; rename one of them",
                )
            for arg in atom.args:
                if arg not in self.args and arg not in self.agents:
                    self.args[arg] = _identifier(arg, taken)
        self.stems = {stem: _identifier(stem, taken) for stem in stems}
        self.actions = {key: _identifier(key, taken) for key in spec.actions}
        # plank grounds no action of an empty parameter list: one of a one-object type
        self.unit, self.now = _identifier("unit", taken), _identifier("now", taken)

    # -- formulas -------------------------------------------------------------------------

    def term(self, name: str) -> str:
        return self.agents.get(name) or self.args[name]

    def atom(self, key: str) -> str:
        atom = _parse_atom(key)
        if atom.name not in self.stems:
            raise InvalidArgumentError(f"atom '{key}' is not declared by the spec")
        return "(" + " ".join([self.stems[atom.name], *(self.term(a) for a in atom.args)]) + ")"

    def atom_key(self, key: str) -> str:
        """The epistemica atom that the EPDDL atom of ``key`` is read back as."""
        parts = self.atom(key)[1:-1].split()
        names = [p.replace("-", "_") for p in parts]
        return names[0] + (f"({', '.join(names[1:])})" if len(names) > 1 else "")

    def formula(self, f: Formula) -> str:
        if isinstance(f, Atom):
            return self.atom(f.key)
        if isinstance(f, (Top, Bottom)):
            return "(true)" if isinstance(f, Top) else "(false)"
        if isinstance(f, Not):
            return f"(not {self.formula(f.operand)})"
        if isinstance(f, (And, Or)):
            op = "and" if isinstance(f, And) else "or"
            parts = []
            for g in _flatten(f, type(f)):
                parts.append(self.formula(g))
            return f"({op} {' '.join(parts)})"
        if isinstance(f, Implies):
            return f"(imply {self.formula(f.left)} {self.formula(f.right)})"
        if isinstance(f, Iff):
            left, right = self.formula(f.left), self.formula(f.right)
            return f"(and (imply {left} {right}) (imply {right} {left}))"
        if isinstance(f, (Believe, Know)):
            return f"([{self.agents[f.agent]}] {self.formula(f.operand)})"
        if isinstance(f, KnowWhether):
            return f"([Kw. {self.agents[f.agent]}] {self.formula(f.operand)})"
        if isinstance(f, (Everybody, EverybodyBelieves)):
            return f"([{self.group(f.group)}] {self.formula(f.operand)})"
        if isinstance(f, (Common, CommonBelief)):
            return f"([C. {self.group(f.group)}] {self.formula(f.operand)})"
        raise InvalidArgumentError(
            f"EPDDL has no formula for {type(f).__name__} ({f})",
            hint="EPDDL formulas have [a], <a>, [Kw. a], [G], [C. G]; no D[G], "
            "announcements or [ACT] modalities",
        )

    def group(self, group: Iterable[str]) -> str:
        return "(" + " ".join(self.agents[a] for a in group) + ")"

    # -- files ----------------------------------------------------------------------------

    def domain(self) -> str:
        lines = [f"(define (domain {self.name})", f"  (:requirements {_REQUIREMENTS})"]
        lines.append(f"  (:action-type-libraries {self.name}-types)")
        if self.stems:
            lines.append("  (:predicates")
            for key_stem, stem in self.stems.items():
                arity = next(len(_parse_atom(k).args) for k in self.spec.atoms
                             if _parse_atom(k).name == key_stem)  # fmt: skip
                params = " ".join(f"?x{i} - entity" for i in range(arity))
                lines.append(f"    ({stem}{' ' + params if params else ''})")
            lines.append("  )")
        lines.append(f"  (:types {self.unit})")
        constants = f"{' '.join(self.args.values())} - object " if self.args else ""
        lines.append(f"  (:constants {constants}{self.now} - {self.unit})")
        for key, action in self.spec.actions.items():
            lines += self.action(key, action)
        lines.append(")")
        return "\n".join(lines) + "\n"

    def action(self, key: str, action: ActionModel) -> list[str]:
        name = self.actions[key]
        events, _relations, _designated, groups = _unconditioned(action, self.model.agents)
        lines = []
        for k, (pre, post) in enumerate(events):
            parts = [f"  (:event {name}-e{k}"]
            if not isinstance(pre, Top):
                parts.append(f"    :precondition {self.formula(pre)}")
            effects = [self.effect(atom, f) for atom, f in post.items()]
            if effects:
                parts.append(f"    :effects (:and {' '.join(effects)})")
            lines.append("\n".join(parts) + ")")
        calls = " ".join(f"({name}-e{k})" for k in range(len(events)))
        observability = " ".join(
            f"({self.agents[agent]} t{k})" for k, members in enumerate(groups) for agent in members
        )
        lines.append(
            f"  (:action {name} :parameters (?u - {self.unit})\n"
            f"    :action-type ({name}-type {calls})\n"
            f"    :observability-conditions (:and {observability}))"
        )
        return lines

    def effect(self, atom: str, f: Formula) -> str:
        if isinstance(f, Top):
            return f"({self.atom(atom)[1:-1]})"
        if isinstance(f, Bottom):
            return f"(not {self.atom(atom)})"
        return f"(iff {self.formula(f)} ({self.atom(atom)[1:-1]}))"

    def library(self) -> str:
        lines = [f"(define (action-type-library {self.name}-types)"]
        lines.append(
            "  (:requirements :lists :partial-observability :multi-pointed-models "
            ":events-conditions)"  # the :conditions section below (plank warns without it)
        )
        for key, action in self.spec.actions.items():
            events, relations, designated, groups = _unconditioned(action, self.model.agents)
            variables = " ".join(f"?e{k}" for k in range(len(events)))
            types = " ".join(f"t{k}" for k in range(len(groups)))
            rels = []
            for k, members in enumerate(groups):
                pairs = " ".join(f"(?e{e} ?e{f})" for e, f in relations[members[0]])
                if pairs:  # plank reads "()" badly; a type left out relates nothing
                    rels.append(f"t{k} (:and {pairs})")
            points = " ".join(f"?e{k}" for k in designated)
            # plank needs a :conditions section: say what holds (trivial precondition or not)
            conditions = " ".join(
                f"?e{k} (:{'' if isinstance(pre, Top) else 'non-'}trivial-precondition)"
                for k, (pre, _) in enumerate(events)
            )
            lines.append(
                f"  (:action-type {self.actions[key]}-type\n    :events ({variables})\n"
                f"    :observability-types ({types})\n    :relations ({' '.join(rels)})\n"
                f"    :designated ({points})\n    :conditions ({conditions}))"
            )
        lines.append(")")
        return "\n".join(lines) + "\n"

    def problem(self) -> str:
        lines = [f"(define (problem {self.name}-problem) (:domain {self.name})"]
        lines.append(f"  (:requirements {_REQUIREMENTS})")
        lines.append(f"  (:agents {' '.join(self.agents.values())})")
        if isinstance(self.model, KnowledgeStructure):
            lines.append(self.theory())
        else:
            lines.append(self.worlds())
        goal = self.formula(self.spec.goal) if self.spec.goal is not None else "(true)"
        lines.append(f"  (:goal {goal})")
        lines.append(")")
        return "\n".join(lines) + "\n"

    def theory(self) -> str:
        """The ``:init`` of a knowledge structure as a finitary S5 theory."""
        s = self.model
        items = []
        everywhere = not (s.law & ~s.designated_states).satisfiable()
        if not everywhere:  # the designated states, a propositional formula
            items.append(self.cubes(s.designated_states & s.law))
        law = self.cubes(s.law)
        if law != "(true)":
            items.append(f"([C. All] {law})")
        for agent in s.agents:
            for slot in sorted(s.relation(agent, "knowledge").slots):
                atom = self.atom(self.slot_atoms[slot])
                items.append(f"([C. All] ([Kw. {self.agents[agent]}] {atom}))")
        body = " ".join(items) if items else "([C. All] (true))"
        return f"  (:init (:and {body}))"

    def cubes(self, f) -> str:
        """A BDD of the structure as a disjunction of disjoint cubes (EPDDL text)."""
        names = self.slot_atoms
        slots = [s for a in self.spec.atoms if (s := self.model.atom_slots.get(a)) is not None]
        terms = []
        for cube in cube_literals(f, slots, MAX_CUBES):
            literals = [self.atom(names[slot]) if value else f"(not {self.atom(names[slot])})"
                        for slot, value in cube]  # fmt: skip
            terms.append(literals[0] if len(literals) == 1 else
                         f"(and {' '.join(literals)})" if literals else "(true)")  # fmt: skip
        if len(terms) == 1:
            return terms[0]
        return f"(or {' '.join(terms)})" if terms else "(false)"

    @cached_property
    def slot_atoms(self) -> dict[int, str]:
        return {slot: atom for atom, slot in self.model.atom_slots.items()}

    def worlds(self) -> str:
        """The ``:init`` of a Kripke model, its worlds listed."""
        m = self.model.minimize()  # bisimilar, and the part the designated worlds reach
        worlds = [f"w{i}" for i in range(m.n_worlds)]
        relations = []
        n_pairs = 0
        for agent in m.agents:
            pairs = _pairs(m.belief_relations[agent])
            n_pairs += len(pairs)
            if n_pairs > MAX_PAIRS:
                raise InvalidArgumentError(
                    f"the initial model has more than {MAX_PAIRS} edges to write",
                    hint="minimize the model first, or use fewer worlds",
                )
            body = " ".join(f"({worlds[i]} {worlds[j]})" for i, j in pairs)
            if body:  # an agent left out relates nothing (plank reads "()" badly)
                relations.append(f"{self.agents[agent]} (:and {body})")
        labels = []
        valuation = m.valuation
        for i, w in enumerate(worlds):
            true = [self.atom(a)[1:-1] for a, v in zip(m.atoms, valuation[i], strict=True) if v]
            body = " ".join(f"({t})" for t in true)
            if true:  # a world left out makes no atom true
                labels.append(f"{w} (:and {body})")
        points = " ".join(worlds[i] for i in m.designated_positions)
        return (
            f"  (:init\n    :worlds ({' '.join(worlds)})\n    :relations ({' '.join(relations)})\n"
            f"    :labels ({' '.join(labels)})\n    :designated ({points}))"
        )


def _parse_atom(key: str) -> Atom:
    atom = as_formula(key)
    if not isinstance(atom, Atom):  # pragma: no cover - a spec's atoms are atoms
        raise InvalidArgumentError(f"'{key}' is not an atom")
    return atom


def _flatten(f: Formula, op: type) -> list[Formula]:
    out, stack = [], [f]
    while stack:
        g = stack.pop()
        if isinstance(g, op):
            stack += [g.right, g.left]
        else:
            out.append(g)
    return out


def _pairs(relation) -> list[tuple[int, int]]:
    sources, targets = relation.edges()
    return sorted(zip(sources.tolist(), targets.tolist(), strict=True))


def _unconditioned(action: ActionModel, agents: Iterable[str]):
    """The action's events split by the truth of its edge conditions.

    Returns ``(events, relations, designated, groups)``: per new event its precondition
    and postcondition, per agent its edges between new events, the new designated events,
    and the agents grouped by equal relations.
    """
    conditions: list[Formula] = []
    for table in action.edges.values():
        for _, _, cond in table:
            if cond is not None and cond not in conditions:
                conditions.append(cond)
    splits = list(itertools.product((True, False), repeat=len(conditions)))
    events, index = [], {}
    for e in range(len(action.events)):
        for s, truth in enumerate(splits):
            literals = [c if t else Not(c) for c, t in zip(conditions, truth, strict=True)]
            pre = action.pre[e]
            for lit in literals:
                pre = lit if isinstance(pre, Top) else And(pre, lit)
            index[e, s] = len(events)
            events.append((pre, dict(action.post[e])))
    relations: dict[str, list[tuple[int, int]]] = {}
    for agent in agents:
        edges = []
        for e, f, cond in action.edges.get(agent, ()):
            for s, truth in enumerate(splits):
                if cond is not None and not truth[conditions.index(cond)]:
                    continue
                edges += [(index[e, s], index[f, t]) for t in range(len(splits))]
        relations[agent] = sorted(set(edges))
    designated = [index[e, s] for e in action.designated_positions for s in range(len(splits))]
    groups: dict[tuple, list[str]] = {}
    for agent in agents:
        groups.setdefault(tuple(relations[agent]), []).append(agent)
    return events, relations, designated, list(groups.values())
