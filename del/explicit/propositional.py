"""Propositional formulas evaluated on many worlds at once: a valuation matrix's rows, or
worlds whose atoms are computed on demand (laws, postconditions, facts about worlds).

Split from :mod:`epistemica.del_.explicit.checker`, which re-exports both functions.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Mapping

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._sets import CONNECTIVES
from epistemica.del_.language.formula import Atom, Bottom, Formula, Not, Top
from epistemica.del_.language.parser import as_formula
from epistemica.del_.language.walk import fold_nodes

__all__ = ["propositional_mask", "propositional_truth", "short_text"]


def short_text(f: Formula) -> str:
    """A formula's text for a message, cut short (deep formulas print long)."""
    with contextlib.suppress(RecursionError):
        text = str(f)
        return text if len(text) <= 60 else text[:57] + "..."
    return type(f).__name__


def propositional_mask(
    formula: Formula | str, val: np.ndarray, column: Mapping[str, int]
) -> np.ndarray:
    """Truth of a propositional formula on each row of a valuation matrix.

    Raises
    ------
    InvalidArgumentError
        If the formula has a modality or names an atom without a column.

    Examples
    --------
    >>> import numpy as np
    >>> val = np.array([[True, False], [True, True]])
    >>> propositional_mask("p & ~q", val, {"p": 0, "q": 1}).tolist()
    [True, False]
    """

    def atom_mask(key: str) -> np.ndarray:
        if key not in column:
            raise InvalidArgumentError(
                f"unknown atom {key!r}", hint=f"declared atoms: {', '.join(column)}"
            )
        return val[:, column[key]]

    return propositional_truth(formula, len(val), atom_mask)


def propositional_truth(
    formula: Formula | str, n_rows: int, atom_mask: Callable[[str], np.ndarray]
) -> np.ndarray:
    """Truth of a propositional formula on ``n_rows`` worlds whose atoms are read lazily.

    The one propositional evaluator of the package: ``atom_mask(key)`` gives the boolean
    truth of the atom named ``key`` (canonical text, as :attr:`Atom.key`) on every world,
    so worlds stored in any form (a valuation matrix, rows of goal indices) are evaluated
    without building a valuation matrix first.

    Raises
    ------
    InvalidArgumentError
        If the formula has a modality (or ``atom_mask`` rejects an atom).

    Examples
    --------
    >>> import numpy as np
    >>> goal = np.array([0, 1, 1])
    >>> propositional_truth("at_1 & ~at_0", 3, lambda key: goal == int(key[-1])).tolist()
    [False, True, True]
    """
    tree = as_formula(formula)

    def combine(f: Formula, values: list[np.ndarray]) -> np.ndarray:
        kind = type(f)
        if kind is Not:
            return ~values[0]
        if kind in CONNECTIVES:
            return CONNECTIVES[kind](*values)
        if kind is Atom:
            return np.asarray(atom_mask(f.key), dtype=bool)
        if kind is Top or kind is Bottom:
            return np.full(n_rows, kind is Top, dtype=bool)
        raise InvalidArgumentError(
            f"expected a propositional formula, found the modality in {short_text(f)}",
            hint="laws, postconditions and facts about worlds cannot mention K, B, C, ...",
        )

    # A fold over the node objects: no recursion, each mask freed after its last use.
    return fold_nodes(tree, combine)
