"""Formulas of dynamic epistemic logic as immutable, hashable trees: the base class, the
propositional nodes and the helpers that build formulas.

The classes mirror the grammar in ``formula.lark``. This module holds the base class
:class:`Formula`, ``true`` and ``false``, atoms, negation and the Boolean connectives; the
modal nodes (the individual and group modalities, announcements, upgrades and named
actions) are in :mod:`~epistemica.del_.language.modalities`. Import both from
:mod:`epistemica.del_`.

``str(formula)`` prints the formula in the concrete syntax with as few parentheses as the
precedence rules allow, so that ``parse_formula(str(f)) == f``. The helpers that rebuild or
join formulas (``map_atoms``, ``with_children``, ``conjunction``, ``disjunction``) build
nodes, so they stay here; the walks ``iter_postorder`` and ``fold`` are in
:mod:`~epistemica.del_.language.walk`, re-exported here.

Examples
--------
>>> from epistemica.del_ import Announce, Atom, Know
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

import operator
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, fields

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language._atom_names import (
    RESERVED_WORDS,
    atom_name,
    canonical_atom,
    split_predicate,
    valid_atom,
)
from epistemica.del_.language.walk import fold, iter_postorder

__all__ = [
    "RESERVED_WORDS",
    "And",
    "Atom",
    "Bottom",
    "Formula",
    "Iff",
    "Implies",
    "Not",
    "Or",
    "TextPart",
    "Top",
    "atom_name",
    "canonical_atom",
    "conjunction",
    "disjunction",
    "fold",
    "iter_postorder",
    "map_atoms",
    "shared",
    "with_children",
]

# Binding strength: higher binds tighter. Unary operators (negation, modalities,
# announcements, actions) all share the top level.
_UNARY, _AND, _OR, _IMPLIES, _IFF = 5, 4, 3, 2, 1

# A piece of printed text: literal text, or a subformula to print where it stands and the
# binding strength below which it needs parentheses.
TextPart = str | tuple["Formula", int]


class Formula:
    """Base class of all formulas.

    Formulas compare and hash structurally. ``&``, ``|`` and ``~`` build conjunctions,
    disjunctions and negations; ``f >> g`` builds the implication ``f -> g``.

    Construction, hashing, comparison, ``str`` and ``repr`` never recurse, so a formula
    nested 10,000 deep or a chain of 100,000 conjuncts is handled in linear time; code
    walking a formula should do the same with
    :func:`~epistemica.del_.language.walk.iter_postorder` or
    :func:`~epistemica.del_.language.walk.fold`.
    """

    # The hash is computed once, at construction, from the (cached) hashes of the
    # children: memo tables hash the same deep formulas over and over, and a lazily
    # computed hash would recurse down the whole tree the first time.
    __slots__ = ("_hash",)
    precedence = _UNARY
    # Whether the node is a modality of agents (K, B, E, C, ...: the classes with
    # own_agents), counted by modal_depth; announcements and actions are not.
    epistemic = False

    def __post_init__(self) -> None:
        values = (getattr(self, name) for name in _field_names(type(self)))
        object.__setattr__(self, "_hash", hash((type(self), *values)))

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other: object) -> bool:
        if self is other:
            return True
        if type(self) is not type(other):
            return NotImplemented
        return _equal(self, other)  # type: ignore[arg-type]

    def __str__(self) -> str:
        out: list[str] = []
        stack: list[TextPart] = [(self, 0)]
        while stack:
            item = stack.pop()
            if isinstance(item, str):
                out.append(item)
                continue
            node, minimum = item
            parts = node.text_parts()
            if node.precedence < minimum:
                parts = ("(", *parts, ")")
            stack.extend(reversed(parts))
        return "".join(out)

    def __repr__(self) -> str:
        out: list[str] = []
        stack: list[str | Formula] = [self]
        while stack:
            item = stack.pop()
            if isinstance(item, str):
                out.append(item)
                continue
            parts: list[str | Formula] = [f"{type(item).__name__}("]
            for i, name in enumerate(_field_names(type(item))):
                value = getattr(item, name)
                parts.append(f"{', ' if i else ''}{name}=")
                parts.append(value if isinstance(value, Formula) else repr(value))
            parts.append(")")
            stack.extend(reversed(parts))
        return "".join(out)

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

    def text_parts(self) -> tuple[TextPart, ...]:
        # The printed text of this node, its subformulas left as (child, minimum) pieces.
        raise NotImplementedError

    def subformulas(self) -> Iterator[Formula]:
        """Every subformula, children before parents (each occurrence once)."""
        return iter_postorder(self)

    def atoms(self) -> frozenset[Atom]:
        """The atoms occurring in the formula."""
        return frozenset(f for f in iter_postorder(self, unique=True) if isinstance(f, Atom))

    def agents(self) -> frozenset[str]:
        """The agents named by the formula's modalities."""
        found: set[str] = set()
        for f in iter_postorder(self, unique=True):
            found.update(f.own_agents())
        return frozenset(found)

    def own_agents(self) -> tuple[str, ...]:
        """The agents this node's own modality names, not its subformulas' (none here)."""
        return ()

    def modal_depth(self) -> int:
        """Nesting depth of epistemic modalities (announcements and actions count 0)."""

        def depth(f: Formula, inner: tuple[int, ...]) -> int:
            return max(inner, default=0) + (1 if f.epistemic else 0)

        return fold(self, depth)


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Top(Formula):
    """The formula ``true``."""

    def text_parts(self) -> tuple[TextPart, ...]:
        return ("true",)


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Bottom(Formula):
    """The formula ``false``."""

    def text_parts(self) -> tuple[TextPart, ...]:
        return ("false",)


@dataclass(frozen=True, slots=True, eq=False, repr=False)
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

    @property
    def key(self) -> str:
        """The canonical text of the atom, used as its key in valuations."""
        return str(self)

    def __post_init__(self) -> None:
        if self.name in RESERVED_WORDS:
            # It would print as a keyword, and the printed formula would not parse back.
            raise InvalidArgumentError(
                f"'{self.name}' is a reserved word and cannot name an atom",
                hint="rename the atom, e.g. to '" + self.name + "_'",
            )
        object.__setattr__(self, "args", tuple(str(a) for a in self.args))
        if not self.args and "(" in self.name:  # Atom("at(r1, g1)") is the predicate atom
            parts = split_predicate(self.name)
            if parts is not None:
                object.__setattr__(self, "name", parts[0])
                object.__setattr__(self, "args", parts[1])
        if not valid_atom(self.name, self.args):
            # It would print as text that does not parse back to this atom.
            raise InvalidArgumentError(
                f"{str(self)!r} is not an atom name",
                hint="an atom is a name (letters, digits, _) or name(arg, ...), e.g. 'p' or "
                "'at(r1, g1)'",
            )
        Formula.__post_init__(self)

    def __str__(self) -> str:
        if not self.args:
            return self.name
        return f"{self.name}({', '.join(self.args)})"

    def text_parts(self) -> tuple[TextPart, ...]:
        return (str(self),)


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Not(Formula):
    """Negation ``~f``."""

    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)

    def text_parts(self) -> tuple[TextPart, ...]:
        return ("~", (self.operand, _UNARY))


class _Binary(Formula):
    __slots__ = ()
    symbol = ""
    right_assoc = False

    def __post_init__(self) -> None:
        # Formula's hash, (type, left, right), without its generic walk over the fields:
        # a generated spec builds hundreds of thousands of connectives.
        left, right = self.left, self.right  # type: ignore[attr-defined]
        object.__setattr__(self, "_hash", hash((type(self), left, right)))

    def children(self) -> tuple[Formula, ...]:
        return (self.left, self.right)  # type: ignore[attr-defined]

    def text_parts(self) -> tuple[TextPart, ...]:
        p = self.precedence
        left_min, right_min = (p + 1, p) if self.right_assoc else (p, p + 1)
        left, right = self.left, self.right  # type: ignore[attr-defined]
        return ((left, left_min), f" {self.symbol} ", (right, right_min))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class And(_Binary):
    """Conjunction ``f & g`` (left-associative)."""

    left: Formula
    right: Formula
    precedence = _AND
    symbol = "&"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Or(_Binary):
    """Disjunction ``f | g`` (left-associative)."""

    left: Formula
    right: Formula
    precedence = _OR
    symbol = "|"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Implies(_Binary):
    """Implication ``f -> g`` (right-associative)."""

    left: Formula
    right: Formula
    precedence = _IMPLIES
    symbol = "->"
    right_assoc = True


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Iff(_Binary):
    """Equivalence ``f <-> g`` (left-associative)."""

    left: Formula
    right: Formula
    precedence = _IFF
    symbol = "<->"


_FIELDS: dict[type, tuple[str, ...]] = {}


def _field_names(cls: type) -> tuple[str, ...]:
    # dataclasses.fields() is slow enough to matter once per node of a 100,000-node formula.
    try:
        return _FIELDS[cls]
    except KeyError:
        names = _FIELDS[cls] = tuple(f.name for f in fields(cls))
        return names


def _equal(first: Formula, second: Formula) -> bool:
    # Pairs still to compare; the cached hashes tell most unequal pairs apart at once.
    stack = [(first, second)]
    while stack:
        a, b = stack.pop()
        if a is b:
            continue
        if type(a) is not type(b) or hash(a) != hash(b):
            return False
        for name in _field_names(type(a)):
            x, y = getattr(a, name), getattr(b, name)
            if isinstance(x, Formula):
                stack.append((x, y))
            elif x != y:
                return False
    return True


def map_atoms(formula: Formula, replace: Callable[[Atom], Formula]) -> Formula:
    """``formula`` with every atom replaced by ``replace(atom)`` (without recursion).

    Examples
    --------
    >>> from epistemica.del_.language.modalities import Know
    >>> f = Know("a", Atom("p") & ~Atom("q"))
    >>> print(map_atoms(f, lambda atom: Atom(atom.name.upper())))
    K[a] (P & ~Q)
    """

    def rebuild(node: Formula, inner: tuple[Formula, ...]) -> Formula:
        return replace(node) if isinstance(node, Atom) else with_children(node, inner)

    return fold(formula, rebuild)


def shared(formula: Formula, table: dict[Formula, Formula]) -> Formula:
    """``formula`` rebuilt from the formulas of ``table``: every subformula equal to one
    already there is that object, and the new ones are added.

    Formulas passed through one table share their equal subformulas, so a memo keyed by
    formula (the checker's truth sets) finds them by identity instead of comparing trees:
    the ground actions of an EPDDL task repeat the same conditions many times.

    Examples
    --------
    >>> table = {}
    >>> first = shared(Atom("p") & Atom("q"), table)
    >>> second = shared(~(Atom("p") & Atom("q")), table)
    >>> second.children()[0] is first
    True
    """

    def rebuild(node: Formula, inner: tuple[Formula, ...]) -> Formula:
        found = table.get(node)
        if found is not None and all(map(operator.is_, inner, found.children())):
            return found
        if not all(map(operator.is_, inner, node.children())):
            node = _rebuilt(node, inner)  # the same formula, its parts from the table
        table[node] = node
        return node

    return fold(formula, rebuild)


def with_children(node: Formula, children: tuple[Formula, ...]) -> Formula:
    """``node`` with its immediate subformulas replaced by ``children`` (same order).

    Examples
    --------
    >>> from epistemica.del_.language.modalities import Know
    >>> print(with_children(Know("a", Atom("p")), (Atom("q"),)))
    K[a] q
    """
    if children == node.children():
        return node
    return _rebuilt(node, children)


def _rebuilt(node: Formula, children: tuple[Formula, ...]) -> Formula:
    """A new ``node`` with ``children`` as its immediate subformulas."""
    parts = iter(children)
    values = [
        next(parts) if isinstance(getattr(node, name), Formula) else getattr(node, name)
        for name in _field_names(type(node))
    ]
    return type(node)(*values)


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
