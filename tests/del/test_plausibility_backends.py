"""The explicit and symbolic plausibility backends against each other and against a naive
reference semantics (tests/plausibility_strategies.py), on random models and formulas."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from plausibility_strategies import Reference, plausibility_formulas, plausibility_models

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.language.parser import parse_formula
from epistemica.del_.symbolic.plausibility import PlausibilityStructure

formulas = plausibility_formulas()


@settings(max_examples=300)
@given(plausibility_models(), formulas)
def test_explicit_backend_follows_the_definitions(model, f):
    expected = Reference.of(model).truth(f)
    assert set(np.flatnonzero(model.truth(f)).tolist()) == expected


# The target: 0 disagreements on at least 1,000 random models (each example is a
# fresh model and formula; hypothesis fails on the first disagreement).
@settings(max_examples=1000)
@given(plausibility_models(), formulas)
def test_symbolic_backend_agrees_with_explicit_on_1000_random_models(model, f):
    structure = PlausibilityStructure.from_explicit(model)
    symbolic = [structure.holds_at(f, model.valuation[w]) for w in range(model.n_worlds)]
    assert symbolic == model.truth(f).tolist()
    assert structure.holds(f) == model.holds(f)


def test_symbolic_from_levels_matches_explicit_from_levels():
    args = (
        ["c", "s", "t"],
        {"m": ["~c & ~s", "~c", "c & s"], "j": ["c"]},
        {"j": ["c", "s"]},
        "c -> s | t",
        ["c", "s"],
    )
    m = PlausibilityModel.from_levels(*args)
    s = PlausibilityStructure.from_levels(*args)
    for text in [
        "B[m] ~c",
        "B[m | s] ~c",
        "Sb[m] (c -> s)",
        "[^^c] B[m | ~s] t",
        "[^c] Sb[m] c",
        "[!s] B[j] c",
        "K[j] c & B[m] ~c",
    ]:
        f = parse_formula(text)
        assert s.holds(f) == m.holds(f), text
        for w in range(m.n_worlds):
            assert s.holds_at(f, m.valuation[w]) == bool(m.truth(f)[w]), (text, w)


def test_both_backends_refuse_what_they_do_not_interpret():
    m = PlausibilityModel.from_levels(["p"], {"a": ["p"]})
    s = PlausibilityStructure.from_explicit(m)
    for backend in (m, s):
        with pytest.raises(InvalidArgumentError, match="do not interpret Common"):
            backend.holds("C[a] p")
        with pytest.raises(InvalidArgumentError, match="unknown atom"):
            backend.holds("B[a] zz")
        with pytest.raises(InvalidArgumentError, match="unknown agent"):
            backend.holds("Sb[x] p")


def test_symbolic_needs_observed_cells():
    cells, ranks = {"a": [0, 1]}, {"a": [0, 0]}
    m = PlausibilityModel(["p"], np.array([[False], [True]]), cells, ranks)
    with pytest.raises(InvalidArgumentError, match="observed atoms"):
        PlausibilityStructure.from_explicit(m)


@given(formulas)
def test_printed_plausibility_formulas_parse_back(f):
    assert parse_formula(str(f)) == f
