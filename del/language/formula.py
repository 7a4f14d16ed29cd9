"""Formulas of dynamic epistemic logic as immutable, hashable trees.

The classes mirror the grammar in ``formula.lark``: atoms, the Boolean connectives, the
individual modalities ``K`` (knowledge), ``B`` (belief) and ``Kw`` (knowing whether), the
group modalities ``E`` (everybody knows), ``C`` (common knowledge), ``D`` (distributed
knowledge), ``EB`` (everybody believes) and ``CB`` (common belief), public announcements
``[!f] g`` and ``<!f> g``, and named actions ``[ACT] g``; for plausibility models,
conditional belief ``B[a | f] g``, safe belief ``Sb[a] f`` and the public soft upgrades
``[^^f] g`` (radical) and ``[^f] g`` (conservative).

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

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, fields
from typing import TypeVar

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language._atom_names import (
    RESERVED_WORDS,
    atom_name,
    canonical_atom,
    split_predicate,
    valid_atom,
)

__all__ = [
    "RESERVED_WORDS",
    "After",
    "And",
    "Announce",
    "AnnounceDiamond",
    "Atom",
    "Believe",
    "Bottom",
    "Common",
    "CommonBelief",
    "ConditionalBelief",
    "ConservativeUpgrade",
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
    "RadicalUpgrade",
    "SafeBelief",
    "Top",
    "atom_name",
    "canonical_atom",
    "conjunction",
    "disjunction",
    "fold",
    "iter_postorder",
    "map_atoms",
    "with_children",
]

# Binding strength: higher binds tighter. Unary operators (negation, modalities,
# announcements, actions) all share the top level.
_UNARY, _AND, _OR, _IMPLIES, _IFF = 5, 4, 3, 2, 1

# A piece of printed text: literal text, or a subformula to print where it stands and the
# binding strength below which it needs parentheses.
_Part = str | tuple["Formula", int]


class Formula:
    """Base class of all formulas.

    Formulas compare and hash structurally. ``&``, ``|`` and ``~`` build conjunctions,
    disjunctions and negations; ``f >> g`` builds the implication ``f -> g``.

    Construction, hashing, comparison, ``str`` and ``repr`` never recurse, so a formula
    nested 10,000 deep or a chain of 100,000 conjuncts is handled in linear time; code
    walking a formula should do the same with :func:`iter_postorder` or :func:`fold`.
    """

    # The hash is computed once, at construction, from the (cached) hashes of the
    # children: memo tables hash the same deep formulas over and over, and a lazily
    # computed hash would recurse down the whole tree the first time.
    __slots__ = ("_hash",)
    precedence = _UNARY

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
        stack: list[_Part] = [(self, 0)]
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

    def text_parts(self) -> tuple[_Part, ...]:
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
            found.update(getattr(f, "group", ()))
            if isinstance(f, _Individual):
                found.add(f.agent)
        return frozenset(found)

    def modal_depth(self) -> int:
        """Nesting depth of epistemic modalities (announcements and actions count 0)."""

        def depth(f: Formula, inner: tuple[int, ...]) -> int:
            return max(inner, default=0) + (1 if isinstance(f, (_Individual, _Group)) else 0)

        return fold(self, depth)


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Top(Formula):
    """The formula ``true``."""

    def text_parts(self) -> tuple[_Part, ...]:
        return ("true",)


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Bottom(Formula):
    """The formula ``false``."""

    def text_parts(self) -> tuple[_Part, ...]:
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

    def text_parts(self) -> tuple[_Part, ...]:
        return (str(self),)


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Not(Formula):
    """Negation ``~f``."""

    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)

    def text_parts(self) -> tuple[_Part, ...]:
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

    def text_parts(self) -> tuple[_Part, ...]:
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


class _Individual(Formula):
    """A modality of one agent: ``OP[agent] operand``."""

    __slots__ = ()
    keyword = ""

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)  # type: ignore[attr-defined]

    def text_parts(self) -> tuple[_Part, ...]:
        operand = self.operand  # type: ignore[attr-defined]
        return (f"{self.keyword}[{self.agent}] ", (operand, _UNARY))  # type: ignore[attr-defined]


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Know(_Individual):
    """``K[a] f``: agent ``a`` knows ``f`` (box over a's knowledge relation)."""

    agent: str
    operand: Formula
    keyword = "K"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Believe(_Individual):
    """``B[a] f``: agent ``a`` believes ``f`` (box over a's belief relation)."""

    agent: str
    operand: Formula
    keyword = "B"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class KnowWhether(_Individual):
    """``Kw[a] f``: agent ``a`` knows whether ``f``, i.e. ``K[a] f | K[a] ~f``."""

    agent: str
    operand: Formula
    keyword = "Kw"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class ConditionalBelief(_Individual):
    """``B[a | c] f``: ``f`` holds at the most plausible worlds of a's cell where ``c`` holds.

    Interpreted in plausibility models only (:mod:`~epistemica.del_.explicit.plausibility`);
    ``B[a | true] f`` is ``B[a] f`` there. ``|`` separates the agent from the condition so
    that ``B[a] (f | g)`` keeps meaning belief in a disjunction.
    """

    agent: str
    condition: Formula
    operand: Formula
    keyword = "B"

    def children(self) -> tuple[Formula, ...]:
        return (self.condition, self.operand)

    def text_parts(self) -> tuple[_Part, ...]:
        return (f"B[{self.agent} | ", (self.condition, 0), "] ", (self.operand, _UNARY))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class SafeBelief(_Individual):
    """``Sb[a] f``: ``f`` holds at every world of a's cell at least as plausible as this one.

    Baltag and Smets' safe belief (the box of the plausibility preorder): it survives every
    truthful revision. Interpreted in plausibility models only.
    """

    agent: str
    operand: Formula
    keyword = "Sb"


class _Group(Formula):
    """A modality of a group of agents: ``OP[a, b] operand``."""

    __slots__ = ()
    keyword = ""

    def __post_init__(self) -> None:
        group = tuple(sorted(set(self.group)))  # type: ignore[attr-defined]
        if not group:
            raise ValueError(f"{self.keyword}[...] needs at least one agent")
        object.__setattr__(self, "group", group)
        Formula.__post_init__(self)

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)  # type: ignore[attr-defined]

    def text_parts(self) -> tuple[_Part, ...]:
        group = ", ".join(self.group)  # type: ignore[attr-defined]
        return (f"{self.keyword}[{group}] ", (self.operand, _UNARY))  # type: ignore[attr-defined]


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Everybody(_Group):
    """``E[a, b] f``: every agent of the group knows ``f``."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "E"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Common(_Group):
    """``C[a, b] f``: ``f`` is common knowledge in the group."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "C"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Distributed(_Group):
    """``D[a, b] f``: ``f`` is distributed knowledge in the group."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "D"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class EverybodyBelieves(_Group):
    """``EB[a, b] f``: every agent of the group believes ``f``."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "EB"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class CommonBelief(_Group):
    """``CB[a, b] f``: ``f`` is common belief in the group.

    ``f`` holds at every world reachable in one or more steps by the union of the group's
    *belief* relations (``C`` uses the knowledge relations).
    """

    group: tuple[str, ...]
    operand: Formula
    keyword = "CB"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Announce(Formula):
    """``[!f] g``: after every truthful public announcement of ``f``, ``g`` holds."""

    announcement: Formula
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.announcement, self.operand)

    def text_parts(self) -> tuple[_Part, ...]:
        return ("[!", (self.announcement, 0), "] ", (self.operand, _UNARY))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class AnnounceDiamond(Formula):
    """``<!f> g``: ``f`` is true (so announceable) and after announcing it ``g`` holds."""

    announcement: Formula
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.announcement, self.operand)

    def text_parts(self) -> tuple[_Part, ...]:
        return ("<!", (self.announcement, 0), "> ", (self.operand, _UNARY))


class _Upgrade(Formula):
    """A public soft announcement ``[OPEN f] g``: the operand holds after the upgrade."""

    __slots__ = ()
    opener = ""

    def children(self) -> tuple[Formula, ...]:
        return (self.upgrade, self.operand)  # type: ignore[attr-defined]

    def text_parts(self) -> tuple[_Part, ...]:
        upgrade, operand = self.upgrade, self.operand  # type: ignore[attr-defined]
        return (f"[{self.opener}", (upgrade, 0), "] ", (operand, _UNARY))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class RadicalUpgrade(_Upgrade):
    """``[^^f] g`` (also ``[⇑f] g``): after the radical upgrade with ``f``, ``g`` holds.

    In every information cell the ``f``-worlds become more plausible than all the others,
    the order within each of the two zones kept (van Benthem's ⇑, Baltag and Smets'
    lexicographic upgrade). Always executable.
    """

    upgrade: Formula
    operand: Formula
    opener = "^^"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class ConservativeUpgrade(_Upgrade):
    """``[^f] g`` (also ``[↑f] g``): after the conservative upgrade with ``f``, ``g`` holds.

    In every information cell only the most plausible ``f``-worlds move to the top; the
    rest of the order is kept (van Benthem's ↑). Always executable.
    """

    upgrade: Formula
    operand: Formula
    opener = "^"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class After(Formula):
    """``[ACT] g``: after every execution of the named action ``ACT``, ``g`` holds.

    The name is resolved against the actions passed to the model checker.
    """

    action: str
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)

    def text_parts(self) -> tuple[_Part, ...]:
        return (f"[{self.action}] ", (self.operand, _UNARY))


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


def iter_postorder(formula: Formula, *, unique: bool = False) -> Iterator[Formula]:
    """The subformulas of ``formula``, children before their parent, without recursion.

    Children are visited left to right (``f.children()``), so a bottom-up evaluator can
    keep the values of the children on a stack of its own, or in a table keyed by the
    subformula.

    Parameters
    ----------
    formula : Formula
    unique : bool
        When true, a subformula equal to one already yielded is skipped together with
        everything below it (each distinct subformula once, as a memoising evaluator
        wants); when false, every occurrence is yielded.

    Yields
    ------
    Formula
        ``formula`` itself comes last.

    Examples
    --------
    >>> p, q = Atom("p"), Atom("q")
    >>> [str(f) for f in iter_postorder((p & q) | p)]
    ['p', 'q', 'p & q', 'p', 'p & q | p']
    >>> [str(f) for f in iter_postorder((p & q) | p, unique=True)]
    ['p', 'q', 'p & q', 'p & q | p']
    """
    seen: set[Formula] = set()
    stack: list[tuple[Formula, bool]] = [(formula, False)]
    while stack:
        node, expanded = stack.pop()
        if expanded:
            if unique:
                if node in seen:
                    continue
                seen.add(node)
            yield node
        elif not (unique and node in seen):
            stack.append((node, True))
            stack.extend((child, False) for child in reversed(node.children()))


_T = TypeVar("_T")


def fold(formula: Formula, combine: Callable[[Formula, tuple[_T, ...]], _T]) -> _T:
    """Compute a value bottom-up over ``formula`` without recursion.

    ``combine(node, values)`` gets a subformula and the values already computed for its
    children (in the order of ``node.children()``). Each distinct subformula is combined
    once, so equal subtrees share their value.

    Examples
    --------
    >>> f = Know("a", Atom("p") & ~Atom("q"))
    >>> fold(f, lambda node, inner: 1 + sum(inner))  # number of nodes
    5
    """
    values: dict[Formula, _T] = {}
    for node in iter_postorder(formula, unique=True):
        values[node] = combine(node, tuple(values[child] for child in node.children()))
    return values[formula]


def map_atoms(formula: Formula, replace: Callable[[Atom], Formula]) -> Formula:
    """``formula`` with every atom replaced by ``replace(atom)`` (without recursion).

    Examples
    --------
    >>> f = Know("a", Atom("p") & ~Atom("q"))
    >>> print(map_atoms(f, lambda atom: Atom(atom.name.upper())))
    K[a] (P & ~Q)
    """

    def rebuild(node: Formula, inner: tuple[Formula, ...]) -> Formula:
        return replace(node) if isinstance(node, Atom) else with_children(node, inner)

    return fold(formula, rebuild)


def with_children(node: Formula, children: tuple[Formula, ...]) -> Formula:
    """``node`` with its immediate subformulas replaced by ``children`` (same order).

    Examples
    --------
    >>> print(with_children(Know("a", Atom("p")), (Atom("q"),)))
    K[a] q
    """
    if children == node.children():
        return node
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
