"""Choosing the backend of a spec: explicit Kripke model or knowledge structure.

:func:`~epistemica.del_.spec.load_spec` and :func:`~epistemica.del_.spec.parse_spec` take
``backend``, one of :data:`BACKENDS`:

- ``"explicit"``: a :class:`~epistemica.del_.KripkeModel` (what planning needs); an
  ``observes`` spec of more than 26 atoms is refused;
- ``"symbolic"``: a :class:`~epistemica.del_.KnowledgeStructure`, built straight from the
  ``observes``/``law``/``actual`` lines (never the 2^n worlds), or converted from the
  explicit worlds of a ``world``/``relation`` spec;
- ``"auto"`` (the default): explicit for what it does well (small models, planning),
  symbolic where enumerating the valuations would not fit: an ``observes`` spec with more
  than :data:`AUTO_ATOMS` atoms, or a model of more than :data:`AUTO_WORLDS` worlds.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import Formula
from epistemica.del_.models import KnowledgeStructure, KripkeModel

__all__ = [
    "AUTO_ATOMS",
    "AUTO_WORLDS",
    "BACKENDS",
    "check_backend",
    "formula_summary",
    "model_builder",
    "on_backend",
]

BACKENDS = ("auto", "explicit", "symbolic")
AUTO_ATOMS = 20
AUTO_WORLDS = 1 << 20


def check_backend(backend: str) -> str:
    """``backend`` if it is one of :data:`BACKENDS`, else ``InvalidArgumentError``."""
    if backend not in BACKENDS:
        raise InvalidArgumentError(
            f"unknown backend {backend!r}", hint=f"use one of: {', '.join(BACKENDS)}"
        )
    return backend


def model_builder(backend: str) -> Callable[..., Any] | None:
    """How an ``observes`` spec's model is built on ``backend`` (``None``: explicitly)."""
    if check_backend(backend) == "explicit":
        return None

    def build(
        atoms: Iterable[str], observes: Mapping, law: Formula, designated: Iterable[str] | None
    ) -> KripkeModel | KnowledgeStructure:
        atoms = list(atoms)
        if backend == "symbolic" or len(atoms) > AUTO_ATOMS:
            return KnowledgeStructure.from_observables(atoms, observes, law, designated)
        return KripkeModel.from_observables(atoms, observes, law, designated)

    return build


def on_backend(model: Any, atoms: Iterable[str], backend: str) -> Any:
    """A compiled spec's model, converted to the symbolic backend if ``backend`` says so."""
    if isinstance(model, KripkeModel) and backend != "explicit":
        if backend == "symbolic" or model.n_worlds > AUTO_WORLDS:
            return model.to_symbolic(atoms)
    return model


def formula_summary(spec: Any, formula: Formula) -> dict[str, Any]:
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
