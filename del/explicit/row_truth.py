"""Truth of propositional formulas remembered per valuation row, across models.

A search over epistemic states evaluates the same preconditions, postconditions and edge
conditions on thousands of small models whose worlds carry a few hundred distinct
valuations between them. A propositional formula's truth at a world depends on that
world's valuation only, so :class:`RowTruth` remembers it per (formula, valuation row)
and answers the next model by dictionary lookups instead of walking the formula again.
Modal formulas, and models with many worlds (where the vectorised evaluator is cheaper
than a loop over rows), go to :func:`~epistemica.del_.explicit.checker.evaluate`
unchanged, so the answer is always the evaluator's.

Examples
--------
>>> from epistemica.del_ import KripkeModel
>>> m = KripkeModel(["u", "v", "w"], {"u": {"p"}, "v": {"p", "q"}, "w": {"p"}},
...                 {"a": [("u", "v")]}, ["u"])
>>> rows = RowTruth()
>>> rows(m, "p & ~q").tolist()
[True, False, True]
>>> rows.entries  # one per combination of p and q met: u and w share theirs
2
>>> rows(m, "~q").tolist(), rows.entries  # only q's values told apart: 2 more
([True, False, True], 4)
"""

from __future__ import annotations

import numpy as np

from epistemica.del_.explicit import checker
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit._sets import CONNECTIVES
from epistemica.del_.explicit.propositional import propositional_mask
from epistemica.del_.language.formula import Atom, Bottom, Formula, Not, Top
from epistemica.del_.language.parser import as_formula
from epistemica.del_.language.walk import iter_nodes

__all__ = ["ROW_LIMIT", "RowTruth"]

#: Models with more worlds than this are evaluated by the vectorised evaluator.
ROW_LIMIT = 64

_PROPOSITIONAL = frozenset((Atom, Not, Top, Bottom, *CONNECTIVES))


class RowTruth:
    """A truth-mask function ``rows(model, formula)`` that remembers propositional
    formulas' values per valuation row.

    Parameters
    ----------
    max_entries : int
        The remembered (formula, row) values are forgotten all at once when they exceed
        this count (about 100 bytes each, so some 50 MB at the default), so memory stays
        bounded on any search. Selective Communication to depth 4 (5,202 states) remembers
        1,902.

    Notes
    -----
    One instance serves one search: formulas are remembered by identity (the search
    keeps its action models alive), rows by their bytes under the model's atom order.
    """

    def __init__(self, max_entries: int = 500_000) -> None:
        self.max_entries = int(max_entries)
        self.entries = 0
        # id(formula) -> (formula, atom keys or None when modal)
        self._kinds: dict[int, tuple[Formula, tuple[str, ...] | None]] = {}
        # (id(formula), model atoms) -> (its atoms' columns, {their bytes in a row: truth})
        self._tables: dict[tuple[int, tuple[str, ...]], tuple[np.ndarray, dict]] = {}

    def __call__(self, model: ExplicitModel, formula: Formula | str) -> np.ndarray:
        """The truth mask of ``formula`` over ``model``'s worlds (read-only)."""
        f = as_formula(formula)
        n = model.n_worlds
        if n > ROW_LIMIT or model.cube is not None:
            return checker.evaluate(model, f)
        known = self._tables.get((id(f), model.atoms))
        if known is None:
            known = self._table(f, model)
            if known is None:
                return checker.evaluate(model, f)
        columns, table = known
        # Rows are told apart by the formula's own atoms only: few combinations recur.
        keys = [row.tobytes() for row in np.packbits(model.valuation[:, columns], axis=1)]
        out = np.empty(n, dtype=bool)
        missing: dict[bytes, int] = {}  # a row of each combination not met before
        for i, key in enumerate(keys):
            value = table.get(key)
            if value is None:
                missing.setdefault(key, i)
            else:
                out[i] = value
        if missing:
            table = self._fill(f, model, columns, missing, table)
            out[:] = [table[key] for key in keys]
        out.setflags(write=False)
        return out

    def _table(self, f: Formula, model: ExplicitModel) -> tuple | None:
        """The formula's atom columns in ``model`` and its (empty) table of values, or
        None when the formula is modal or names an atom the model lacks."""
        atoms = self._atoms_of(f)
        if atoms is None:
            return None
        columns = [model.atom_column(key) for key in atoms]
        if any(c is None for c in columns):  # the evaluator decides what that means
            return None
        known = (np.array(columns, dtype=np.intp), {})
        self._tables[(id(f), model.atoms)] = known
        return known

    def _fill(self, f, model, columns, missing: dict[bytes, int], table: dict) -> dict:
        """Evaluate ``f`` on one row per missing combination and remember the values."""
        if self.entries + len(missing) > self.max_entries:
            for _, old in self._tables.values():
                old.clear()
            self.entries = 0
        atoms = self._atoms_of(f) or ()
        rows = list(missing.values())
        values = propositional_mask(
            f, model.valuation[np.ix_(rows, columns)], {a: j for j, a in enumerate(atoms)}
        )
        table.update(zip(missing, values.tolist(), strict=True))
        self.entries += len(missing)
        return table

    def _atoms_of(self, f: Formula) -> tuple[str, ...] | None:
        known = self._kinds.get(id(f))
        if known is None or known[0] is not f:
            atoms: set[str] | None = set()
            for node in iter_nodes(f):
                if type(node) not in _PROPOSITIONAL:
                    atoms = None
                    break
                if type(node) is Atom:
                    atoms.add(node.key)
            known = (f, None if atoms is None else tuple(sorted(atoms)))
            self._kinds[id(f)] = known
        return known[1]
