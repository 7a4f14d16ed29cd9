"""Walks over formula objects by identity: nothing hashed or compared.

:func:`~epistemica.del_.language.formula.iter_postorder` and
:func:`~epistemica.del_.language.formula.fold` treat equal subformulas as one (they hash and
compare); a parsed text has equal subtrees as separate objects, and the values folded
(truth sets, BDDs) can be large. These walk each node object once, without recursion.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TypeVar

from epistemica.del_.language.formula import Formula

__all__ = ["fold_nodes", "iter_nodes"]

_T = TypeVar("_T")


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
