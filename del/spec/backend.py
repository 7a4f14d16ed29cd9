"""Choosing the backend for a spec: explicit Kripke model or knowledge structure.

``auto`` keeps the explicit backend for what it does well (small models, planning) and
switches to the symbolic one where enumerating the valuations would not fit: an
``observes`` spec with more than :data:`AUTO_ATOMS` atoms, or a model of more than
:data:`AUTO_WORLDS` worlds. The symbolic path builds the structure straight from the
spec's ``observes``/``law``/``actual`` lines, never the 2^n worlds.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import Formula
from epistemica.del_.models import KnowledgeStructure, KripkeModel
from epistemica.del_.spec._document import Spec
from epistemica.del_.spec._document import load_spec as _load_spec

__all__ = ["AUTO_ATOMS", "AUTO_WORLDS", "BACKENDS", "formula_summary", "load_spec"]

BACKENDS = ("auto", "explicit", "symbolic")
AUTO_ATOMS = 20
AUTO_WORLDS = 1 << 20


def load_spec(path: str | Path, backend: str = "auto") -> Spec:
    """Load a spec whose ``model`` is a ``KripkeModel`` or a ``KnowledgeStructure``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> text = "agents " + ", ".join(f"c{i}" for i in range(30)) + "\\natoms m0..m29\\n"
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "big.epi"
    >>> _ = path.write_text(text)
    >>> type(load_spec(path).model).__name__
    'KnowledgeStructure'
    >>> load_spec(path, "symbolic").holds("~Kw[c1] m1")
    True
    """
    if backend not in BACKENDS:
        raise InvalidArgumentError(
            f"unknown backend {backend!r}", hint=f"use one of: {', '.join(BACKENDS)}"
        )
    if backend == "explicit":
        return _load_spec(path)
    spec = _load_spec(path, observables=_chooser(backend))
    model = spec.model
    if isinstance(model, KripkeModel) and (backend == "symbolic" or model.n_worlds > AUTO_WORLDS):
        return dataclasses.replace(spec, model=model.to_symbolic(spec.atoms))
    return spec


def _chooser(backend: str) -> Callable[..., Any]:
    def build(
        atoms: Iterable[str], observes: Mapping, law: Formula, designated: Iterable[str] | None
    ) -> KripkeModel | KnowledgeStructure:
        atoms = list(atoms)
        if backend == "symbolic" or len(atoms) > AUTO_ATOMS:
            return KnowledgeStructure.from_observables(atoms, observes, law, designated)
        return KripkeModel.from_observables(atoms, observes, law, designated)

    return build


def formula_summary(spec: Spec, formula: Formula) -> dict[str, Any]:
    """Truth of ``formula`` in a symbolic spec: at the designated states and in counts."""
    model = spec.model
    n_points = model.count_designated()
    n_points_true = model.count_designated(formula, spec.actions)
    return {
        "holds": n_points_true == n_points,
        "n_designated": n_points,
        "n_designated_true": n_points_true,
        "n_worlds": model.n_worlds,
        "n_true": model.count(formula, spec.actions),
    }
