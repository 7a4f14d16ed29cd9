"""Walks over formula trees, without recursion.

:func:`iter_postorder` and :func:`fold` treat equal subformulas as one (they hash and
compare), as a memoising evaluator wants. :func:`iter_nodes` and :func:`fold_nodes` walk
each node object once by identity, nothing hashed or compared: a parsed text has equal
subtrees as separate objects, and the values folded (truth sets, BDDs) can be large.

The walks only call ``children()``, so this module needs the formula classes for type
hints only, and :mod:`~epistemica.del_.language.formula` (whose methods walk) can import it.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, TypeVar

if TYPE_CHECKING:  # formula.py imports this module
    from epistemica.del_.language.formula import Formula

__all__ = ["fold", "fold_nodes", "iter_nodes", "iter_postorder"]

_T = TypeVar("_T")


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
    >>> from epistemica.del_.language.formula import Atom
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


def fold(formula: Formula, combine: Callable[[Formula, tuple[_T, ...]], _T]) -> _T:
    """Compute a value bottom-up over ``formula`` without recursion.

    ``combine(node, values)`` gets a subformula and the values already computed for its
    children (in the order of ``node.children()``). Each distinct subformula is combined
    once, so equal subtrees share their value.

    Examples
    --------
    >>> from epistemica.del_.language.formula import Atom
    >>> from epistemica.del_.language.modalities import Know
    >>> f = Know("a", Atom("p") & ~Atom("q"))
    >>> fold(f, lambda node, inner: 1 + sum(inner))  # number of nodes
    5
    """
    values: dict[Formula, _T] = {}
    for node in iter_postorder(formula, unique=True):
        values[node] = combine(node, tuple(values[child] for child in node.children()))
    return values[formula]


def iter_nodes(formula: Formula) -> Iterator[Formula]:
    """Every node object of ``formula`` once, in no particular order, without recursion.

    Distinct by identity, not by equality: no subformula is hashed or compared, so this is
    the cheap walk for checks that look at each node alone (the names a formula uses,
    whether it is propositional), also on formulas whose equal subtrees are separate
    objects (a parsed text).

    Examples
    --------
    >>> from epistemica.del_.language.formula import Atom
    >>> p = Atom("p")
    >>> sorted(str(f) for f in iter_nodes(p & ~p))
    ['p', 'p & ~p', '~p']
    """
    seen: set[int] = set()
    stack = [formula]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        yield node
        stack.extend(node.children())


def fold_nodes(formula: Formula, combine: Callable[[Formula, list[_T]], _T]) -> _T:
    """Like :func:`fold`, but over node objects (by identity), freeing each value as soon
    as its last parent has used it.

    Nothing is hashed or compared, so this is the fold for large values (truth sets,
    BDDs) over parsed text, whose equal subtrees are often separate objects; a node
    object shared by several parents is still combined once.

    Examples
    --------
    >>> from epistemica.del_.language.formula import Atom
    >>> p = Atom("p")
    >>> calls = []
    >>> fold_nodes(p & ~p, lambda node, inner: calls.append(node) or 1 + sum(inner))
    4
    >>> len(calls)  # p, ~p and the conjunction: the shared p is combined once
    3
    """
    done: dict[int, _T] = {}
    uses: dict[int, int] = {}  # parents still to combine, per node
    stack: list[tuple[Formula, bool]] = [(formula, False)]
    while stack:
        node, expanded = stack.pop()
        if id(node) in done:
            continue
        children = node.children()
        if children and not expanded:
            stack.append((node, True))
            for child in children:
                uses[id(child)] = uses.get(id(child), 0) + 1
                stack.append((child, False))
            continue
        values = [done[id(c)] for c in children]
        for c in children:
            uses[id(c)] -= 1
            if not uses[id(c)]:
                del done[id(c)]
        done[id(node)] = combine(node, values)
    return done[id(formula)]
