"""SMCDEL's text format, read into a spec and written from one.

SMCDEL (van Benthem, van Eijck, Gattinger and Su's symbolic model checker) reads a
knowledge structure and queries::

    VARS 1,2,3                 -- the atoms (numbers)
    LAW  Top                   -- the states: the valuations satisfying the law
    OBS  alice: 2,3            -- what each agent observes
         bob:   1,3
    TRUE? {1,2} alice knows that 2      -- at the state where exactly 1, 2 are true
    VALID? [ ! (1|2|3) ] ...            -- at every state
    WHERE? bob knows whether 1          -- the states where it holds

which is a spec's ``atoms``/``law``/``observes``: :func:`parse_smcdel` compiles a file into a
:class:`~epistemica.del_.spec.Spec` whose every world is designated, with one claim per
``VALID?`` (the formula) and per ``TRUE? {S}`` (``S -> formula``, ``S`` the conjunction of
the literals of the state), and keeps the ``WHERE?`` queries. Atom ``N`` is named ``pN``;
agents keep their names. Group announcements ``[alice, bob ! f] g`` (the group learns
whether ``f``, the others that it did) become actions of the spec, ``[ACT] g``.
:func:`to_smcdel` writes an S5 spec whose worlds are distinct valuations (a model from
observables, or any S5 model whose relations are "agree on some atoms"), with a
``TRUE?`` or ``VALID?`` per claim; comment lines record the spec's names
(``-- epistemica atom 1: at(r1, g1)``), which :func:`parse_smcdel` reads back.

Examples
--------
>>> text = '''VARS 1,2,3
... LAW Top
... OBS alice: 2,3
...     bob: 1,3
...     carol: 1,2
... VALID? [ ! (1|2|3) ] [ ! ~ (alice knows whether 1) & ~ (bob knows whether 2)
...   & ~ (carol knows whether 3) ] [ ! ~ (alice knows whether 1) & ~ (bob knows whether 2)
...   & ~ (carol knows whether 3) ] (1 & 2 & 3)
... WHERE? alice knows whether 1'''
>>> smc = parse_smcdel(text)
>>> smc.spec.atoms, [smc.spec.holds(c.formula) for c in smc.spec.checks]
(('p1', 'p2', 'p3'), [True])
>>> [line for line in to_smcdel(smc.spec).splitlines() if line.startswith("VARS")]
['VARS 1,2,3']
"""

from __future__ import annotations

import functools
import itertools
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from epistemica.del_.errors import InvalidArgumentError, ParseError, SpecError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.formats._epddl_syntax import Source, position
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
    conjunction,
    disjunction,
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
from epistemica.del_.models import KnowledgeStructure, KripkeModel
from epistemica.del_.spec import Check, Spec, read_source

__all__ = [
    "SMCDEL_GRAMMAR",
    "SmcdelFile",
    "is_smcdel",
    "load_smcdel",
    "parse_smcdel",
    "to_smcdel",
]

#: Path of the grammar file of SMCDEL's text format.
SMCDEL_GRAMMAR = Path(__file__).with_name("smcdel.lark")

# Above this many atoms the model is a knowledge structure (as the spec backend's "auto").
_SYMBOLIC_ATOMS = 20
_NAME = re.compile(r"-- epistemica (atom|agent) (\S+): (.+)$", re.MULTILINE)
_KEYWORDS = {"VARS", "LAW", "OBS", "Top", "Bot", "Not", "not", "iff", "AND", "OR", "XOR",
             "ONEOF", "ForAll", "Forall", "Exists", "K", "Kw"}  # fmt: skip
_PROPOSITIONAL = (Top, Bottom, Atom, Not, And, Or, Implies, Iff)


@dataclass(frozen=True)
class SmcdelFile:
    """A compiled SMCDEL file: the spec, and the ``WHERE?`` queries (text, formula)."""

    spec: Spec
    where: tuple[tuple[str, Formula], ...] = ()


def is_smcdel(path: str | Path) -> bool:
    """Whether a path names an SMCDEL file (``.smcdel``, or SMCDEL's ``.smcdel.txt``)."""
    name = str(path).lower()
    return name.endswith(".smcdel") or name.endswith(".smcdel.txt")


def load_smcdel(path: str | Path, backend: str = "auto") -> SmcdelFile:
    """Read (once, bounded: :func:`read_source`) and compile an SMCDEL file (see
    :func:`parse_smcdel`)."""
    return parse_smcdel(read_source(path, "SMCDEL file"), str(path), backend)


def parse_smcdel(text: str, filename: str = "<smcdel>", backend: str = "auto") -> SmcdelFile:
    """Compile SMCDEL's text format; ``backend`` as for specs (``auto``: symbolic above 20
    atoms).

    Raises
    ------
    ParseError, SpecError
        Located in ``text``.
    """
    try:
        tree = _lark().parse(text)
    except UnexpectedInput as exc:
        token = getattr(exc, "token", None)
        found = f"'{token}'" if token is not None and token.type != "$END" else "the end"
        raise ParseError(
            f"unexpected {found}", line=exc.line, column=exc.column, source=text,
            filename=filename,
            hint="SMCDEL's format is VARS 1,2 LAW f OBS a: 1 ... then TRUE?/VALID?/WHERE? jobs",
        ) from None  # fmt: skip
    return _Reader(Source(text, filename), backend).read(tree)


@functools.cache
def _lark() -> Lark:
    return Lark.open(str(SMCDEL_GRAMMAR), parser="lalr", propagate_positions=True,
                     maybe_placeholders=True)  # fmt: skip


class _Reader:
    def __init__(self, src: Source, backend: str) -> None:
        self.src = src
        self.backend = backend
        names = {(kind, key): value.strip() for kind, key, value in _NAME.findall(src.text)}
        self.atom_names = {k: v for (kind, k), v in names.items() if kind == "atom"}
        self.agent_names = {k: v for (kind, k), v in names.items() if kind == "agent"}
        self.actions: dict[str, ActionModel] = {}
        self.agents: tuple[str, ...] = ()

    def read(self, tree: Tree) -> SmcdelFile:
        ints, law_tree, *rest = tree.children
        obs = [t for t in rest if t.data == "obs_line"]
        jobs = [t for t in rest if t.data != "obs_line"]
        self.vars = [int(t) for t in ints.children]
        self.atoms = {n: self.atom_names.get(str(n), f"p{n}") for n in self.vars}
        observes: dict[str, list[str]] = {}
        for line in obs:
            who, seen = line.children
            agent = self.agent(who)
            observes.setdefault(agent, [])
            observes[agent] += [self.atoms[self.var(t)] for t in seen.children]
        self.agents = tuple(observes)
        law = self.formula(law_tree)
        if not all(isinstance(g, _PROPOSITIONAL) for g in law.subformulas()):
            raise self.src.error("the LAW must be propositional", law_tree, "a boolean formula")
        atoms = list(self.atoms.values())
        symbolic = self.backend == "symbolic" or (
            self.backend == "auto" and len(atoms) > _SYMBOLIC_ATOMS
        )
        build = KnowledgeStructure if symbolic else KripkeModel
        try:
            model = build.from_observables(atoms, observes, law)
        except InvalidArgumentError as exc:
            raise self.src.error(exc.message, law_tree, exc.hint) from None
        checks, where = [], []
        for k, job in enumerate(jobs, start=1):
            keyword, *parts = job.children
            f = self.formula(parts[-1])
            text = " ".join(self.src.text[job.meta.start_pos : job.meta.end_pos].split())
            line, column = position(job)
            if job.data == "where_q":
                where.append((text, f))
                continue
            if job.data == "true_q":
                state = self.state(parts[0], law)
                if not _satisfied_somewhere(model, state):
                    raise self.src.error(
                        "the state of this TRUE? violates the LAW", parts[0],
                        "list the atoms true at a state that satisfies the LAW",
                    )  # fmt: skip
                f = Implies(state, f)
            checks.append(Check(f"{keyword} #{k}", text, f, True, self.src.filename, line, column))
        spec = Spec(
            model=model, actions=dict(self.actions), goal=None, checks=tuple(checks),
            agents=self.agents, atoms=tuple(atoms), filename=self.src.filename,
            source=self.src.text,
        )  # fmt: skip
        return SmcdelFile(spec, tuple(where))

    # -- names --------------------------------------------------------------------------

    def var(self, token: Token) -> int:
        n = int(token)
        if n not in self.atoms:
            raise self.src.error(
                f"atom {n} is not in VARS", token, f"VARS {', '.join(map(str, self.vars))}"
            )
        return n

    def agent(self, token: Token) -> str:
        name = self.agent_names.get(str(token), str(token))
        if self.agents and name not in self.agents:
            raise self.src.error(
                f"agent '{token}' is not in OBS", token, f"agents: {', '.join(self.agents)}"
            )
        return name

    def state(self, tree: Tree, law: Formula) -> Formula:
        ints = tree.children[0]
        true = {self.var(t) for t in ints.children} if ints is not None else set()
        literals = [
            Atom(self.atoms[n]) if n in true else Not(Atom(self.atoms[n])) for n in self.vars
        ]
        return conjunction(literals)

    # -- formulas -----------------------------------------------------------------------

    def formula(self, tree: Tree | Token) -> Formula:
        if isinstance(tree, Token):  # pragma: no cover - every formula is a tree
            raise AssertionError(tree)
        kind, kids = tree.data, [k for k in tree.children if not _punctuation(k)]
        f = self.formula
        if kind == "top":
            return Top()
        if kind == "bot":
            return Bottom()
        if kind == "prop":
            return Atom(self.atoms[self.var(kids[0])])
        if kind == "neg":
            return Not(f(kids[0]))
        if kind in ("conj2", "disj2"):
            return (And if kind == "conj2" else Or)(f(kids[0]), f(kids[1]))
        if kind in ("conj", "disj", "xor", "oneof"):
            parts = [f(k) for k in kids[0].children]
            return _list_formula(kind, parts)
        if kind == "impl":
            return Implies(f(kids[0]), f(kids[1]))
        if kind == "equi":
            return Iff(f(kids[0]), f(kids[1]))
        if kind == "k":
            return Know(self.agent(kids[0]), f(kids[-1]))
        if kind == "kw":
            return KnowWhether(self.agent(kids[0]), f(kids[-1]))
        if kind == "kw_all":
            return conjunction(KnowWhether(self.agent(kids[0]), f(k)) for k in kids[-1].children)
        if kind in ("ck", "ckw", "dk", "dkw"):
            group = tuple(self.agent(t) for t in kids[0].children)
            op = Common if kind in ("ck", "ckw") else Distributed
            g = f(kids[-1])
            return op(group, g) if kind in ("ck", "dk") else Or(op(group, g), op(group, Not(g)))
        if kind in ("pub", "dpub"):
            g = Announce(f(kids[0]), f(kids[1]) if kind == "pub" else Not(f(kids[1])))
            return g if kind == "pub" else Not(g)
        if kind in ("pubw", "dpubw"):
            a, g = f(kids[0]), f(kids[1])
            if kind == "dpubw":
                g = Not(g)
            both = And(Implies(a, Announce(a, g)), Implies(Not(a), Announce(Not(a), g)))
            return both if kind == "pubw" else Not(both)
        if kind in ("ann", "annw", "dann", "dannw"):
            group = tuple(self.agent(t) for t in kids[0].children)
            name = self.announcement(group, f(kids[1]), kind in ("annw", "dannw"))
            g = f(kids[2])
            return After(name, g) if kind in ("ann", "annw") else Not(After(name, Not(g)))
        if kind in ("forall", "exists"):
            props = [self.var(t) for t in kids[0].children]
            body = f(kids[1])
            if not all(isinstance(g, _PROPOSITIONAL) for g in body.subformulas()):
                raise self.src.error(
                    "Forall/Exists over a modal formula", tree,
                    "epistemica reads boolean quantifiers over propositional formulas only",
                )  # fmt: skip
            return _quantify(body, [self.atoms[n] for n in props], kind == "forall")
        raise AssertionError(kind)  # pragma: no cover

    def announcement(self, group: tuple[str, ...], f: Formula, whether: bool) -> str:
        """The action ``[G ! f]`` (or ``[G ?! f]``): G learns whether f, the others that
        G did; named ``announce_K``."""
        events = ["yes", "no"]
        relations = {
            a: [("yes", "yes"), ("no", "no")]
            if a in group
            else [(e, g) for e in events for g in events]
            for a in self.agents
        }
        action = ActionModel(events, {"yes": f, "no": Not(f)}, {}, relations,
                             events if whether else ["yes"])  # fmt: skip
        name = f"announce_{len(self.actions) + 1}"
        self.actions[name] = action
        return name


def _satisfied_somewhere(model, f: Formula) -> bool:
    if hasattr(model, "truth_mask"):
        return bool(model.truth_mask(f).any())
    return model.count(f) > 0


def _punctuation(item) -> bool:
    return isinstance(item, Token) and item.type not in ("NAME", "INT")


def _list_formula(kind: str, parts: list[Formula]) -> Formula:
    if kind == "conj":
        return conjunction(parts)
    if kind == "disj":
        return disjunction(parts)
    if kind == "xor":  # odd parity, as SMCDEL's Xor
        result: Formula = Bottom()
        for p in parts:
            result = (
                Or(And(result, Not(p)), And(Not(result), p))
                if not isinstance(result, Bottom)
                else p
            )
        return result
    return disjunction(  # ONEOF: exactly one
        conjunction([p, *(Not(q) for j, q in enumerate(parts) if j != i)])
        for i, p in enumerate(parts)
    )


def _quantify(body: Formula, atoms: list[str], universal: bool) -> Formula:
    out = []
    for values in itertools.product((True, False), repeat=len(atoms)):
        out.append(_substitute(body, dict(zip(atoms, values, strict=True))))
    return conjunction(out) if universal else disjunction(out)


def _substitute(f: Formula, values: dict[str, bool]) -> Formula:
    if isinstance(f, Atom):
        if f.key in values:
            return Top() if values[f.key] else Bottom()
        return f
    if isinstance(f, (Top, Bottom)):
        return f
    if isinstance(f, Not):
        return Not(_substitute(f.operand, values))
    return type(f)(_substitute(f.left, values), _substitute(f.right, values))


# -- writing ------------------------------------------------------------------------------


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
    if not hasattr(model, "valuation"):  # pragma: no cover - a symbolic spec
        model = model.to_kripke()
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
    if not all(observed.values()):
        # SMCDEL's OBS lists at least one atom: who sees nothing sees an atom always true.
        pad = len(atoms) + 1
        lines.append(f"-- epistemica constant {pad}: always true, observed by who sees nothing")
        numbers.append(pad)
        law = f"({law}) & {pad}"
        observed = {a: seen or [pad] for a, seen in observed.items()}
    lines.append("VARS " + ",".join(map(str, numbers)))
    lines.append("LAW  " + law)
    obs = [f"{agents[a]}: {','.join(map(str, seen))}" for a, seen in observed.items()]
    lines.append("OBS  " + "\n     ".join(obs))
    writer = _FormulaWriter(number, agents, spec.actions)
    points = model.designated_positions
    for check in spec.checks:
        try:
            text = writer.write(check.formula)
        except InvalidArgumentError as exc:
            raise SpecError(f"claim \"{check.name}\": {exc.message}", line=check.line,
                            column=check.column, source=spec.source, filename=spec.filename,
                            hint=exc.hint) from None  # fmt: skip
        if not check.expected:
            text = f"~ ({text})"
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
        ok = re.fullmatch(r"[a-zA-Z][a-zA-Z0-9]*", a) and a not in _KEYWORDS
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
