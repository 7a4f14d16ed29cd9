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
:func:`~epistemica.del_.formats.smcdel_export.to_smcdel` writes a spec back (explicit S5
models whose worlds are distinct valuations, and knowledge structures of any size), with
a ``TRUE?`` or ``VALID?`` per claim; comment lines record the spec's names
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
>>> from epistemica.del_.formats.smcdel_export import to_smcdel
>>> [line for line in to_smcdel(smc.spec).splitlines() if line.startswith("VARS")]
['VARS 1,2,3']
"""

from __future__ import annotations

import functools
import itertools
import re
from dataclasses import dataclass
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from epistemica.del_.errors import InvalidArgumentError, ParseError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.formats._epddl_syntax import Source, position
from epistemica.del_.formats.kinds import is_smcdel
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
    map_atoms,
)
from epistemica.del_.language.modalities import (
    After,
    Announce,
    Common,
    Distributed,
    Know,
    KnowWhether,
)
from epistemica.del_.models import KnowledgeStructure, KripkeModel
from epistemica.del_.spec import Check, Spec, check_claim_count, check_token_count, read_source

__all__ = [
    "MAX_ONEOF",
    "SMCDEL_GRAMMAR",
    "SmcdelFile",
    "is_smcdel",
    "load_smcdel",
    "parse_smcdel",
]

#: Path of the grammar file of SMCDEL's text format.
SMCDEL_GRAMMAR = Path(__file__).with_name("smcdel.lark")

# Above this many atoms the model is a knowledge structure (as the spec backend's "auto").
_SYMBOLIC_ATOMS = 20
_NAME = re.compile(r"-- epistemica (atom|agent) (\S+): (.+)$", re.MULTILINE)
_JOB = re.compile(r"((?:TRUE|VALID|WHERE)\?)")
_PROPOSITIONAL = (Top, Bottom, Atom, Not, And, Or, Implies, Iff)


@dataclass(frozen=True)
class SmcdelFile:
    """A compiled SMCDEL file: the spec, and the ``WHERE?`` queries (text, formula)."""

    spec: Spec
    where: tuple[tuple[str, Formula], ...] = ()


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
    check_token_count(text, filename, "SMCDEL file")  # before parsing: bounded memory
    check_claim_count(text, filename, claim=_JOB)  # each job is a claim of a spec
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

    def formula(self, tree: Tree) -> Formula:
        """The formula of a parse tree, built children first on an explicit stack (a
        chain ``1|2|...`` or ``~~...1`` is as deep as it is long: no recursion limit).
        The tree is consumed: its children are dropped once read (its position stays, for
        errors), so that a large law's parse tree is freed before the model is built."""
        done: list[Formula] = []
        stack: list[tuple[Tree, bool]] = [(tree, False)]
        while stack:
            node, ready = stack.pop()
            kids = [k for k in node.children if not _punctuation(k)]
            subtrees = _subtrees(node.data, kids)
            if not ready:
                stack.append((node, True))
                stack.extend((t, False) for t in reversed(subtrees))
                continue
            cut = len(done) - len(subtrees)
            values = done[cut:]
            del done[cut:]
            done.append(self.build(node, kids, values))
        tree.children = []
        return done[0]

    def build(self, tree: Tree, kids: list, v: list[Formula]) -> Formula:
        """The formula of node ``tree`` given its subformulas ``v`` (:func:`_subtrees`)."""
        kind = tree.data
        if kind in ("top", "bot", "prop"):
            if kind == "prop":
                return Atom(self.atoms[self.var(kids[0])])
            return Top() if kind == "top" else Bottom()
        if kind == "neg":
            return Not(v[0])
        if kind in _BINARY:
            return _BINARY[kind](v[0], v[1])
        if kind in ("conj", "disj", "xor", "oneof"):
            if kind == "oneof" and len(v) > MAX_ONEOF:
                raise self.src.error(
                    f"ONEOF of {len(v):,} formulas: more than {MAX_ONEOF:,} (its expansion "
                    "grows with the square of their number)", tree,
                    "split the ONEOF, or state it as a LAW over fewer variables",
                )  # fmt: skip
            return _list_formula(kind, v)
        if kind in ("k", "kw"):
            return (Know if kind == "k" else KnowWhether)(self.agent(kids[0]), v[0])
        if kind == "kw_all":
            return conjunction(KnowWhether(self.agent(kids[0]), g) for g in v)
        if kind in ("ck", "ckw", "dk", "dkw"):
            group = tuple(self.agent(t) for t in kids[0].children)
            op = Common if kind in ("ck", "ckw") else Distributed
            g = v[0]
            return op(group, g) if kind in ("ck", "dk") else Or(op(group, g), op(group, Not(g)))
        if kind in ("pub", "dpub"):
            g = Announce(v[0], v[1] if kind == "pub" else Not(v[1]))
            return g if kind == "pub" else Not(g)
        if kind in ("pubw", "dpubw"):
            a, g = v[0], v[1] if kind == "pubw" else Not(v[1])
            both = And(Implies(a, Announce(a, g)), Implies(Not(a), Announce(Not(a), g)))
            return both if kind == "pubw" else Not(both)
        if kind in ("ann", "annw", "dann", "dannw"):
            group = tuple(self.agent(t) for t in kids[0].children)
            name = self.announcement(group, v[0], kind in ("annw", "dannw"))
            return After(name, v[1]) if kind in ("ann", "annw") else Not(After(name, Not(v[1])))
        if kind in ("forall", "exists"):
            return self.quantified(tree, [self.var(t) for t in kids[0].children], v[0])
        raise AssertionError(kind)  # pragma: no cover

    def quantified(self, tree: Tree, props: list[int], body: Formula) -> Formula:
        """``Forall``/``Exists`` over ``props``: the body once per assignment, bounded."""
        if not all(isinstance(g, _PROPOSITIONAL) for g in body.subformulas()):
            raise self.src.error(
                "Forall/Exists over a modal formula", tree,
                "epistemica reads boolean quantifiers over propositional formulas only",
            )  # fmt: skip
        size = sum(1 for _ in body.subformulas())
        if len(props) > 30 or size << len(props) > MAX_EXPANSION:
            raise self.src.error(
                f"this quantifier over {len(props)} variables expands its body of {size:,} "
                f"nodes 2^{len(props)} times: more than {MAX_EXPANSION:,} nodes", tree,
                "quantify over fewer variables (epistemica expands a quantifier in full)",
            )  # fmt: skip
        return _quantify(body, [self.atoms[n] for n in props], tree.data == "forall")

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


#: The node kinds of two subformulas joined by one connective.
_BINARY = {"conj2": And, "disj2": Or, "impl": Implies, "equi": Iff}
_NO_FORMULA = frozenset(("top", "bot", "prop"))
_LAST = frozenset(("k", "kw", "ck", "ckw", "dk", "dkw", "forall", "exists"))
_LISTS = frozenset(("conj", "disj", "xor", "oneof"))


def _subtrees(kind: str, kids: list) -> list[Tree]:
    """The subtrees of a node of kind ``kind`` that are formulas, in order."""
    if kind in _NO_FORMULA:
        return []
    if kind == "neg":
        return [kids[0]]
    if kind in _LAST:
        return [kids[-1]]
    if kind in _LISTS:
        return list(kids[0].children)
    if kind == "kw_all":
        return list(kids[-1].children)
    if kind in ("ann", "annw", "dann", "dannw"):
        return [kids[1], kids[2]]
    return [kids[0], kids[1]]  # binary connectives and public announcements


def _punctuation(item) -> bool:
    return isinstance(item, Token) and item.type not in ("NAME", "INT")


def _list_formula(kind: str, parts: list[Formula]) -> Formula:
    if kind in ("conj", "disj") and len(parts) > _LONG_LIST:
        return _balanced(And if kind == "conj" else Or, parts)
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


#: Longer AND/OR lists are read as balanced trees: a left fold of thousands of parts is
#: a formula as deep as it is long (printing it, hashing it, recursing on it overflows).
_LONG_LIST = 64
#: A longer ONEOF is refused: it expands to as many conjunctions of as many literals.
MAX_ONEOF = 1_000
#: A Forall/Exists whose expansion (the body's nodes times 2^variables) is larger is refused.
MAX_EXPANSION = 1 << 20


def _balanced(op: type, parts: list[Formula]) -> Formula:
    """``parts`` joined by ``op`` as a tree of logarithmic depth (the same truth)."""
    level = list(parts)
    while len(level) > 1:
        pairs = [op(level[i], level[i + 1]) for i in range(0, len(level) - 1, 2)]
        level = pairs + ([level[-1]] if len(level) % 2 else [])
    return level[0]


def _quantify(body: Formula, atoms: list[str], universal: bool) -> Formula:
    out = []
    for values in itertools.product((True, False), repeat=len(atoms)):
        out.append(_substitute(body, dict(zip(atoms, values, strict=True))))
    return conjunction(out) if universal else disjunction(out)


def _substitute(f: Formula, values: dict[str, bool]) -> Formula:
    def value(atom: Atom) -> Formula:
        if atom.key not in values:
            return atom
        return Top() if values[atom.key] else Bottom()

    return map_atoms(f, value)  # without recursion: a body may be a long chain


# -- writing ------------------------------------------------------------------------------
