"""Models from observables are evaluated on bitsets; they must agree with explicit models."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import InvalidArgumentError, KripkeModel

from epistemic_strategies import explicit_copy, formulas

ATOMS = ("p", "q", "r")


@st.composite
def observable_models(draw):
    observes = {agent: draw(st.lists(st.sampled_from(ATOMS), unique=True)) for agent in ("a", "b")}
    law = draw(
        st.one_of(
            st.none(),
            formulas(announcements=False, max_leaves=4).filter(lambda f: f.modal_depth() == 0),
        )
    )
    actual = draw(st.lists(st.sampled_from(ATOMS), unique=True))
    try:
        return KripkeModel.from_observables(ATOMS, observes, law=law, designated=actual)
    except InvalidArgumentError:  # the law excludes the actual world, or everything
        return KripkeModel.from_observables(ATOMS, observes, designated=actual)


@settings(max_examples=150)
@given(observable_models(), formulas(max_leaves=10))
def test_bitset_evaluation_matches_explicit_model(model, f):
    assert model.cube is not None
    reference = explicit_copy(model)
    assert model.truth_set(f) == reference.truth_set(f)
    assert model.holds(f) == reference.holds(f)


@settings(max_examples=60)
@given(observable_models(), formulas(max_leaves=6), formulas(max_leaves=6))
def test_announcement_on_bitsets_matches_explicit_model(model, announced, f):
    reference = explicit_copy(model)
    if not reference.holds(f"<!{announced}> true"):
        with pytest.raises(InvalidArgumentError):
            model.announce(announced)
        return
    after, reference_after = model.announce(announced), reference.announce(announced)
    assert set(after.worlds) == set(reference_after.worlds)
    assert after.truth_set(f) == reference_after.truth_set(f)


@pytest.mark.parametrize("n_atoms", [3, 6, 7, 9])
def test_codes_name_the_valuations(n_atoms):
    """World c has atom j true iff bit n-1-j of c is set (around the 64-bit word size)."""
    atoms = [f"x{j}" for j in range(n_atoms)]
    model = KripkeModel.from_observables(atoms, {"a": atoms[:1]}, designated=atoms[1:2])
    assert model.n_worlds == 2**n_atoms
    assert model.designated == (1 << (n_atoms - 2),)
    for code in (0, 1, 2**n_atoms - 1, 5 % 2**n_atoms):
        expected = {atoms[j] for j in range(n_atoms) if code >> (n_atoms - 1 - j) & 1}
        assert model.valuation_of(code) == expected
    # a sees only x0: knows x0's value, nothing else.
    assert model.holds("Kw[a] x0 & ~Kw[a] x1")
    assert np.array_equal(model.truth_mask("x0"), model.valuation[:, 0])


def test_law_restricts_worlds():
    model = KripkeModel.from_observables(["p", "q"], {"a": ["p"]}, law="p -> q", designated=["q"])
    assert {model.valuation_of(w) for w in model.worlds} == {
        frozenset(),
        frozenset({"q"}),
        frozenset({"p", "q"}),
    }
    assert model.holds("~p & K[a] ~p & ~Kw[a] q & K[a] (p -> q)")
    assert model.announce("q").holds("~p & K[a] ~p & K[a] q")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"law": "p & ~p"}, "no valuation satisfies the law"),
        ({"law": "p", "designated": []}, "violates the law"),
        ({"law": "K[a] p"}, "propositional"),
        ({"law": "s"}, "unknown atom"),
        ({"designated": ["s"]}, "unknown atom"),
    ],
)
def test_bad_observable_models(kwargs, message):
    with pytest.raises(InvalidArgumentError, match=message):
        KripkeModel.from_observables(["p", "q"], {"a": ["p"]}, **kwargs)


def test_many_atoms_are_refused_with_a_hint():
    atoms = [f"x{j}" for j in range(27)]
    with pytest.raises(InvalidArgumentError, match="at most 26"):
        KripkeModel.from_observables(atoms, {"a": atoms})


def test_muddy_children_twenty():
    """A million worlds: the bitset path runs the full puzzle (published answer: n-1 rounds)."""
    n = 20
    atoms = [f"m{i}" for i in range(n)]
    model = KripkeModel.from_observables(
        atoms, {f"c{i}": atoms[:i] + atoms[i + 1 :] for i in range(n)}, designated=atoms
    )
    model = model.announce(" | ".join(atoms))
    nobody = " & ".join(f"~Kw[c{i}] m{i}" for i in range(n))
    rounds = 0
    while model.holds(nobody):
        model = model.announce(nobody)
        rounds += 1
    assert rounds == n - 1
    assert model.n_worlds == 1
    assert all(itertools.starmap(lambda i, a: model.holds(f"K[c{i}] {a}"), enumerate(atoms)))
