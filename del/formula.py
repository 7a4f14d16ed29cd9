"""Formulas of dynamic epistemic logic as immutable, hashable trees.

The classes mirror the grammar in ``formula.lark``: atoms, the Boolean connectives, the
individual modalities ``K`` (knowledge), ``B`` (belief) and ``Kw`` (knowing whether), the
group modalities ``E`` (everybody knows), ``C`` (common knowledge), ``D`` (distributed
knowledge), ``EB`` (everybody believes) and ``CB`` (common belief), public announcements
``[!f] g`` and ``<!f> g``, and named actions ``[ACT] g``.

``str(formula)`` prints the formula in the concrete syntax with as few parentheses as the
precedence rules allow, so that ``parse_formula(str(f)) == f``.

Examples
--------
>>> p, q = Atom("p"), Atom("q")
>>> f = Know("a", p & ~q)
>>> print(f)
K[a] (p & ~q)
>>> print(Announce(p, Know("a", p)))
[!p] K[a] p
>>> sorted(atom.name for atom in f.atoms())
['p', 'q']
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, fields

__all__ = [
    "After",
    "And",
    "Announce",
    "AnnounceDiamond",
    "Atom",
    "Believe",
    "Bottom",
    "Common",
    "CommonBelief",
    "Distributed",
    "Everybody",
    "EverybodyBelieves",
    "Formula",
    "Iff",
    "Implies",
    "Know",
    "KnowWhether",
    "Not",
    "Or",
    "Top",
    "canonical_atom",
    "conjunction",
    "disjunction",
]

# Binding strength: higher binds tighter. Unary operators (negation, modalities,
# announcements, actions) all share the top level.
_UNARY, _AND, _OR, _IMPLIES, _IFF = 5, 4, 3, 2, 1

_ATOM_TEXT = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\((.*)\))?\s*$")


def canonical_atom(text: str) -> str:
    """Return the canonical spelling of an atom written as text.

    Predicate atoms are spelled ``name(arg1, arg2)`` with one space after each comma, so
    that ``"at(r1,g1)"`` and ``"at( r1 , g1 )"`` name the same atom.

    Examples
    --------
    >>> canonical_atom("at(r1,g1)")
    'at(r1, g1)'
    >>> canonical_atom(" p ")
    'p'
    """
    match = _ATOM_TEXT.match(text)
    if match is None:
        return text.strip()
    name, args = match.groups()
    if args is None:
        return name
    return f"{name}({', '.join(a.strip() for a in args.split(','))})"


class Formula:
    """Base class of all formulas.

    Formulas compare and hash structurally. ``&``, ``|`` and ``~`` build conjunctions,
    disjunctions and negations; ``f >> g`` builds the implication ``f -> g``.
    """

    # The hash is cached: memo tables hash the same (deep) formulas over and over.
    __slots__ = ("_hash",)
    precedence = _UNARY

    def __and__(self, other: Formula) -> Formula:
        return And(self, other)

    def __or__(self, other: Formula) -> Formula:
        return Or(self, other)

    def __invert__(self) -> Formula:
        return Not(self)

    def __rshift__(self, other: Formula) -> Formula:
        return Implies(self, other)

    def children(self) -> tuple[Formula, ...]:
        """The immediate subformulas, in left-to-right order."""
        return ()

    def subformulas(self) -> Iterator[Formula]:
        """Every subformula, children before parents (each occurrence once)."""
        for child in self.children():
            yield from child.subformulas()
        yield self

    def atoms(self) -> frozenset[Atom]:
        """The atoms occurring in the formula."""
        return frozenset(f for f in self.subformulas() if isinstance(f, Atom))

    def agents(self) -> frozenset[str]:
        """The agents named by the formula's modalities."""
        found: set[str] = set()
        for f in self.subformulas():
            found.update(getattr(f, "group", ()))
            if isinstance(f, _Individual):
                found.add(f.agent)
        return frozenset(found)

    def modal_depth(self) -> int:
        """Nesting depth of epistemic modalities (announcements and actions count 0)."""
        inner = max((c.modal_depth() for c in self.children()), default=0)
        return inner + (1 if isinstance(self, (_Individual, _Group)) else 0)

    def _wrap(self, child: Formula, minimum: int) -> str:
        text = str(child)
        return f"({text})" if child.precedence < minimum else text


@dataclass(frozen=True, slots=True)
class Top(Formula):
    """The formula ``true``."""

    def __str__(self) -> str:
        return "true"


@dataclass(frozen=True, slots=True)
class Bottom(Formula):
    """The formula ``false``."""

    def __str__(self) -> str:
        return "false"


@dataclass(frozen=True, slots=True)
class Atom(Formula):
    """A propositional atom ``p`` or a predicate atom ``at(r1, g1)``.

    Parameters
    ----------
    name : str
        The predicate or proposition name.
    args : tuple of str
        Arguments of a predicate atom; empty for a plain proposition.
    """

    name: str
    args: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "args", tuple(str(a) for a in self.args))

    @property
    def key(self) -> str:
        """The canonical text of the atom, used as its key in valuations."""
        return str(self)

    def __str__(self) -> str:
        if not self.args:
            return self.name
        return f"{self.name}({', '.join(self.args)})"


@dataclass(frozen=True, slots=True)
class Not(Formula):
    """Negation ``~f``."""

    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)

    def __str__(self) -> str:
        return "~" + self._wrap(self.operand, _UNARY)


class _Binary(Formula):
    __slots__ = ()
    symbol = ""
    right_assoc = False

    def children(self) -> tuple[Formula, ...]:
        return (self.left, self.right)  # type: ignore[attr-defined]

    def __str__(self) -> str:
        p = self.precedence
        left_min, right_min = (p + 1, p) if self.right_assoc else (p, p + 1)
        left = self._wrap(self.left, left_min)  # type: ignore[attr-defined]
        right = self._wrap(self.right, right_min)  # type: ignore[attr-defined]
        return f"{left} {self.symbol} {right}"


@dataclass(frozen=True, slots=True)
class And(_Binary):
    """Conjunction ``f & g`` (left-associative)."""

    left: Formula
    right: Formula
    precedence = _AND
    symbol = "&"


@dataclass(frozen=True, slots=True)
class Or(_Binary):
    """Disjunction ``f | g`` (left-associative)."""

    left: Formula
    right: Formula
    precedence = _OR
    symbol = "|"


@dataclass(frozen=True, slots=True)
class Implies(_Binary):
    """Implication ``f -> g`` (right-associative)."""

    left: Formula
    right: Formula
    precedence = _IMPLIES
    symbol = "->"
    right_assoc = True


@dataclass(frozen=True, slots=True)
class Iff(_Binary):
    """Equivalence ``f <-> g`` (left-associative)."""

    left: Formula
    right: Formula
    precedence = _IFF
    symbol = "<->"


class _Individual(Formula):
    """A modality of one agent: ``OP[agent] operand``."""

    __slots__ = ()
    keyword = ""

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)  # type: ignore[attr-defined]

    def __str__(self) -> str:
        operand = self._wrap(self.operand, _UNARY)  # type: ignore[attr-defined]
        return f"{self.keyword}[{self.agent}] {operand}"  # type: ignore[attr-defined]


@dataclass(frozen=True, slots=True)
class Know(_Individual):
    """``K[a] f``: agent ``a`` knows ``f`` (box over a's knowledge relation)."""

    agent: str
    operand: Formula
    keyword = "K"


@dataclass(frozen=True, slots=True)
class Believe(_Individual):
    """``B[a] f``: agent ``a`` believes ``f`` (box over a's belief relation)."""

    agent: str
    operand: Formula
    keyword = "B"


@dataclass(frozen=True, slots=True)
class KnowWhether(_Individual):
    """``Kw[a] f``: agent ``a`` knows whether ``f``, i.e. ``K[a] f | K[a] ~f``."""

    agent: str
    operand: Formula
    keyword = "Kw"


class _Group(Formula):
    """A modality of a group of agents: ``OP[a, b] operand``."""

    __slots__ = ()
    keyword = ""

    def __post_init__(self) -> None:
        group = tuple(sorted(set(self.group)))  # type: ignore[attr-defined]
        if not group:
            raise ValueError(f"{self.keyword}[...] needs at least one agent")
        object.__setattr__(self, "group", group)

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)  # type: ignore[attr-defined]

    def __str__(self) -> str:
        operand = self._wrap(self.operand, _UNARY)  # type: ignore[attr-defined]
        return f"{self.keyword}[{', '.join(self.group)}] {operand}"  # type: ignore[attr-defined]


@dataclass(frozen=True, slots=True)
class Everybody(_Group):
    """``E[a, b] f``: every agent of the group knows ``f``."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "E"


@dataclass(frozen=True, slots=True)
class Common(_Group):
    """``C[a, b] f``: ``f`` is common knowledge in the group."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "C"


@dataclass(frozen=True, slots=True)
class Distributed(_Group):
    """``D[a, b] f``: ``f`` is distributed knowledge in the group."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "D"


@dataclass(frozen=True, slots=True)
class EverybodyBelieves(_Group):
    """``EB[a, b] f``: every agent of the group believes ``f``."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "EB"


@dataclass(frozen=True, slots=True)
class CommonBelief(_Group):
    """``CB[a, b] f``: ``f`` is common belief in the group.

    ``f`` holds at every world reachable in one or more steps by the union of the group's
    *belief* relations (``C`` uses the knowledge relations).
    """

    group: tuple[str, ...]
    operand: Formula
    keyword = "CB"


@dataclass(frozen=True, slots=True)
class Announce(Formula):
    """``[!f] g``: after every truthful public announcement of ``f``, ``g`` holds."""

    announcement: Formula
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.announcement, self.operand)

    def __str__(self) -> str:
        return f"[!{self.announcement}] {self._wrap(self.operand, _UNARY)}"


@dataclass(frozen=True, slots=True)
class AnnounceDiamond(Formula):
    """``<!f> g``: ``f`` is true (so announceable) and after announcing it ``g`` holds."""

    announcement: Formula
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.announcement, self.operand)

    def __str__(self) -> str:
        return f"<!{self.announcement}> {self._wrap(self.operand, _UNARY)}"


@dataclass(frozen=True, slots=True)
class After(Formula):
    """``[ACT] g``: after every execution of the named action ``ACT``, ``g`` holds.

    The name is resolved against the actions passed to the model checker.
    """

    action: str
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)

    def __str__(self) -> str:
        return f"[{self.action}] {self._wrap(self.operand, _UNARY)}"


def _cached_hash(self: Formula) -> int:
    try:
        return self._hash
    except AttributeError:
        value = hash((type(self), *(getattr(self, f.name) for f in fields(self))))
        object.__setattr__(self, "_hash", value)
        return value


for _node in (
    Top, Bottom, Atom, Not, And, Or, Implies, Iff, Know, Believe, KnowWhether,
    Everybody, Common, Distributed, EverybodyBelieves, CommonBelief, Announce,
    AnnounceDiamond, After,
):  # fmt: skip
    _node.__hash__ = _cached_hash


def conjunction(formulas: Iterable[Formula]) -> Formula:
    """Fold formulas with ``&`` from the left; the empty conjunction is ``true``.

    Examples
    --------
    >>> print(conjunction([Atom("p"), Atom("q"), Atom("r")]))
    p & q & r
    """
    result: Formula | None = None
    for f in formulas:
        result = f if result is None else And(result, f)
    return Top() if result is None else result


def disjunction(formulas: Iterable[Formula]) -> Formula:
    """Fold formulas with ``|`` from the left; the empty disjunction is ``false``."""
    result: Formula | None = None
    for f in formulas:
        result = f if result is None else Or(result, f)
    return Bottom() if result is None else result
