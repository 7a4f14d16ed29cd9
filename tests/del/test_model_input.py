"""Arguments of the model classes: wrong types and unwritable atom names are refused, and
both backends follow one rule for atoms that no world makes true (issue 22)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import (
    Atom,
    InvalidArgumentError,
    KnowledgeStructure,
    KripkeModel,
    ModelError,
    parse_formula,
)

from epistemic_strategies import formulas, models


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((["w"], None, {"a": []}, "w"), "valuation must be a mapping"),
        ((["w"], {"w": []}, None, "w"), "relations must be a mapping"),
        ((["w"], {"w": "p"}, {"a": []}, "w"), "must be an iterable of atom names"),
        (("w", {}, {"a": []}, "w"), "worlds must be a sequence"),
        ((["w"], {"w": ["p q"]}, {"a": []}, "w"), "'p q' in the valuation of 'w' is not an"),
        ((["w"], {"w": [""]}, {"a": []}, "w"), "'' in the valuation of 'w' is not an atom"),
        ((["w"], {"w": []}, {"a": ["w"]}, "w"), "holds 'w', not a \\(world, world\\) pair"),
        ((["w"], {"w": []}, {"a": [("w",)]}, "w"), "not a \\(world, world\\) pair"),
        ((["w"], {"w": []}, {"a": [("w", "w", "w")]}, "w"), "not a \\(world, world\\) pair"),
        ((["w"], {"w": []}, {"a": [1]}, "w"), "holds 1, not a"),
        ((["w"], {"w": []}, {"a": None}, "w"), "relation of a must be an iterable"),
        (([["w"]], {}, {"a": []}, ["w"]), "world name must be a string or a number"),
        ((["w"], {"w": []}, {"a": []}, None), "unknown world None in designated"),
    ],
)
def test_bad_arguments_are_clear_errors(args, message):
    with pytest.raises(InvalidArgumentError, match=message):
        KripkeModel(*args)


@pytest.mark.parametrize("name", ["p q", "", "1p", "p-q", "at(r1 g1)", "K"])
def test_unwritable_atom_names_are_refused_everywhere(name):
    with pytest.raises(InvalidArgumentError):
        Atom(name)
    with pytest.raises(InvalidArgumentError):
        KripkeModel.from_observables([name], {"a": []})
    with pytest.raises(InvalidArgumentError):
        KnowledgeStructure.from_observables([name], {"a": []})
    with pytest.raises(InvalidArgumentError):
        KripkeModel(["w"], {}, {"a": []}, "w", atoms=[name])


def test_an_atom_written_as_predicate_text_is_the_predicate_atom():
    assert Atom("at(r1,g1)") == parse_formula("at(r1, g1)")


def test_declared_atoms_that_no_world_makes_true_are_false_on_both_backends():
    m = KripkeModel(["u", "v"], {"u": ["p"]}, {"a": [("u", "v"), ("v", "u")]}, "u",
                    atoms=["p", "q"])  # fmt: skip
    s = KnowledgeStructure.from_kripke(m)  # no 'unknown atom': q is declared
    for f in ("~q", "K[a] ~q", "~p | q -> ~q"):
        assert m.holds(f) == s.holds(f)
    assert m.truth_set("q") == set() and s.count("q") == 0
    assert m.atoms == ("p", "q") and set(s.atoms) == {"p", "q"}


def test_undeclared_atoms_are_unknown_on_both_backends():
    m = KripkeModel(["u"], {"u": ["p"]}, {"a": [("u", "u")]}, "u", atoms=["p", "q"])
    for model in (m, KnowledgeStructure.from_kripke(m)):
        with pytest.raises(InvalidArgumentError, match="unknown atom 'r'") as caught:
            model.holds("K[a] r")
        assert "declared atoms: p, q" in caught.value.hint
    with pytest.raises(InvalidArgumentError, match="did you mean 'p'"):
        m.holds("pp")


def test_the_valuation_names_only_declared_atoms():
    with pytest.raises(ModelError, match="atom 'r' in the valuation of 'u' is not declared"):
        KripkeModel(["u"], {"u": ["r"]}, {"a": []}, "u", atoms=["p"])


@settings(max_examples=150, deadline=None)
@given(
    models("s5", max_worlds=4, atoms=("p", "q", "r")),
    formulas(atoms=("p", "q", "r"), max_leaves=6, announcements=False),
    st.sampled_from(["x", "p_", "rr"]),
)
def test_both_backends_agree_on_every_declared_atom_and_refuse_the_rest(model, f, stray):
    """Random models declare p, q, r, some true nowhere; both backends give the same truth,
    and both refuse an atom outside the vocabulary."""
    s = KnowledgeStructure.from_kripke(model)
    assert s.holds(f) == model.holds(f)
    assert s.count(f) == len(model.truth_set(f))
    for backend in (model, s):
        with pytest.raises(InvalidArgumentError, match="unknown atom"):
            backend.holds(Atom(stray) & f)
