"""``epistemica show SPEC --html OUT``: a spec's model as one self-contained HTML page.

The page (:func:`epistemica.html_view.model_page`) lists the worlds, each agent's
relations and the designated worlds, draws the model, shows the spec's claims with the
worlds where each holds (computed here by :func:`epistemica.del_.evaluate`), and has a box
that evaluates static formulas in the page.
"""

from __future__ import annotations

import re

from epistemica.del_ import KripkeModel, Spec, evaluate
from epistemica.html_view import check_writable, model_page, write_page
from epistemica.model_json import model_to_json, world_names

__all__ = ["write_model_view"]

# An announcement, a diamond or an action: a bracket no modality letter opens.
_DYNAMIC = re.compile(r"(?<![A-Za-z])\[|<!")


def write_model_view(spec: Spec, model: KripkeModel, path: str, title: str, limit=None) -> None:
    """Write the page of ``model`` (a model of ``spec``) with the spec's claims evaluated
    on it (truth sets by :func:`epistemica.del_.evaluate`)."""
    check_writable(path)
    names = world_names(model)
    ordered = [names[w] for w in model.worlds]
    claims = []
    for check in spec.checks:
        truth = evaluate(model, check.formula, spec.actions)
        designated = bool(truth[model.designated_positions].all())
        claims.append(
            {
                "name": check.name,
                "formula": check.text,
                "expected": check.expected,
                "holds": designated,
                "worlds": [n for n, t in zip(ordered, truth.tolist(), strict=True) if t],
            }
        )
    example = next((c["formula"] for c in claims if not _DYNAMIC.search(c["formula"])), "")
    data = model_to_json(model, spec.atoms, limit)
    write_page(path, model_page(data, title, claims, example))
