"""The explicit checker: formulas of any depth or width, and a memory budget it keeps."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import (
    ActionModel,
    After,
    And,
    Announce,
    Atom,
    Implies,
    Know,
    KripkeModel,
    Not,
    Or,
    public_announcement,
)
from epistemica.del_.budget import (
    MemoryBudgetError,
    budget_scope,
    current_budget,
    estimate_explicit_bytes,
)
from epistemica.del_.explicit.checker import propositional_mask

from epistemic_strategies import explicit_copy, formulas

DEEP = 10_000
WIDE = 100_000


def _small_models():
    """The same two-atom S5 model from observables (bitsets) and as explicit worlds."""
    cube = KripkeModel.from_observables(["p", "q"], {"a": ["q"], "b": ["p"]}, designated=["p"])
    worlds = list(cube.worlds)
    plain = KripkeModel(
        worlds,
        {w: cube.valuation_of(w) for w in worlds},
        {g: [(w, v) for w in worlds for v in cube.successors(g, w)] for g in cube.agents},
        list(cube.designated),
    )
    return cube, plain


@pytest.mark.parametrize("which", [0, 1])
def test_negations_nested_ten_thousand_deep(which):
    model = _small_models()[which]
    f = Atom("p")
    for _ in range(DEEP):  # an even number of negations is the atom itself
        f = Not(f)
    assert np.array_equal(model.truth_mask(f), model.truth_mask("p"))
    assert model.holds(f)


@pytest.mark.parametrize("which", [0, 1])
def test_knowledge_nested_ten_thousand_deep(which):
    """In S5, K[a] K[a] ... p is K[a] p; alternating K[a] K[b] reaches every world."""
    model = _small_models()[which]
    same, alternating = Atom("q"), Atom("q")
    for i in range(DEEP):
        same = Know("a", same)
        alternating = Know("a" if i % 2 else "b", alternating)
    assert np.array_equal(model.truth_mask(same), model.truth_mask("K[a] q"))
    assert not model.truth_mask(alternating).any()  # q is false somewhere


@pytest.mark.parametrize(("which", "left_deep"), [(0, True), (1, False)])
def test_flat_chains_of_a_hundred_thousand_terms(which, left_deep):
    model = _small_models()[which]
    terms = [Atom("p"), Atom("q"), Not(Atom("q"))] * (WIDE // 3)
    conj = disj = impl = terms[0]
    for t in terms[1:]:
        conj = And(conj, t) if left_deep else And(t, conj)
        disj = Or(disj, t) if left_deep else Or(t, disj)
        impl = Implies(t, impl)
    assert not model.truth_mask(conj).any()  # q & ~q
    assert model.truth_mask(disj).all()  # q | ~q
    # t1 -> (t2 -> ... -> p): false only where every premise holds, impossible (q, ~q).
    assert model.truth_mask(impl).all()


def test_deep_law_is_evaluated_without_recursion():
    law = Atom("p")
    for _ in range(DEEP):
        law = Not(Not(law))
    val = np.array([[True, False], [False, True]])
    assert propositional_mask(law, val, {"p": 0, "q": 1}).tolist() == [True, False]


def test_deep_announcements_on_bitsets():
    """[!p][!p]...[!p] K[a] p: after announcing p, a knows it, however often it is said."""
    cube, plain = _small_models()
    f = Know("a", Atom("p"))
    for _ in range(2_000):
        f = Announce(Atom("p"), f)
    assert cube.truth_mask(f).all() and plain.truth_mask(f).all()


@st.composite
def _observable_models(draw, atoms=("p", "q", "r")):
    observes = {a: draw(st.lists(st.sampled_from(atoms), unique=True)) for a in ("a", "b")}
    actual = draw(st.lists(st.sampled_from(atoms), unique=True))
    return KripkeModel.from_observables(atoms, observes, designated=actual)


@settings(max_examples=80, deadline=None)
@given(_observable_models(), formulas(max_leaves=5), formulas(max_leaves=8))
def test_public_actions_on_bitsets_match_explicit_products(model, pre, f):
    """[tell] f on bitsets (an announcement) equals the product update on explicit worlds."""
    actions = {"tell": public_announcement(pre, ["a", "b"])}
    reference = explicit_copy(model)
    g = After("tell", f)
    assert model.truth_set(g, actions) == reference.truth_set(g, actions)
    assert model.holds(g, actions) == reference.holds(g, actions)


def test_sparse_cube_is_checked_on_its_live_worlds():
    """Few live codes of many: the compact path, with the same answers as explicit worlds."""
    atoms = [f"x{i}" for i in range(12)]
    model = KripkeModel.from_observables(atoms, {"a": atoms[:5], "b": atoms[3:]}, designated=[])
    few = model.announce(" & ".join(f"~x{i}" for i in range(2, 12)))  # 4 of 4,096 codes
    assert few.n_worlds == 4 and few.cube.sparse()
    reference = explicit_copy(few)
    for f in ("K[a] x0", "Kw[b] x1", "C[a, b] ~x5", "<!x0> K[b] x0", "D[a, b] x1"):
        assert few.truth_set(f) == reference.truth_set(f)
    assert few.announce("~x1").n_worlds == 2


def test_budget_refuses_before_allocating_and_names_the_alternative():
    model = KripkeModel.from_observables([f"m{i}" for i in range(20)], {"a": []})
    with pytest.raises(MemoryBudgetError) as error:
        model.holds("K[a] m1", memory_budget=10_000)
    message = str(error.value)
    assert "KiB" in message and "symbolic" in message
    with pytest.raises(MemoryBudgetError):
        KripkeModel.from_observables([f"m{i}" for i in range(20)], {}, memory_budget=1000)
    assert model.holds("~K[a] m1")  # the default budget is enough


def test_budget_scope_nests_and_restores():
    default = current_budget()
    with budget_scope(123):
        assert current_budget() == 123
        with budget_scope(None):
            assert current_budget() == 123
    assert current_budget() == default


def test_actions_on_twenty_six_atoms_are_bounded():
    """A public action stays on bitsets; any other action is refused before a product."""
    atoms = [f"m{i}" for i in range(26)]
    agents = ["a", "b"]
    model = KripkeModel.from_observables(atoms, {"a": atoms[1:], "b": atoms[:1]}, designated=[])
    tell = public_announcement("m0", agents)
    assert model.holds("[tell] K[a] m0", {"tell": tell})
    whisper = ActionModel(
        ["e", "skip"],
        {"e": "m0"},
        {},
        {"a": [("e", "e"), ("skip", "skip")], "b": [("e", "skip"), ("skip", "skip")]},
        "e",
    )
    with pytest.raises(MemoryBudgetError, match="symbolic"):
        model.holds("[whisper] K[a] m0", {"whisper": whisper})


def test_estimate_grows_with_the_atoms():
    small, large = estimate_explicit_bytes(10, 3), estimate_explicit_bytes(30, 3)
    assert large == small * 2**20  # bitsets of 2^n bits
    assert estimate_explicit_bytes(24, 24, materialize=True) > 2**24 * 8 * 24


def test_a_few_worlds_of_a_large_cube_are_named_without_listing_all():
    atoms = [f"m{i}" for i in range(20)]
    model = KripkeModel.from_observables(atoms, {"a": atoms[1:]}, designated=["m0", "m19"])
    after = model.announce("m0 | m1")  # codes 0 .. 2^18 - 1 are gone
    assert after.worlds_at([0, 1]) == (1 << 18, (1 << 18) + 1)
    assert after.designated == ((1 << 19) + 1,)
    assert after.worlds_at(after.designated_positions) == after.designated
    assert after.valuation_of((1 << 19) + 1) == {"m0", "m19"}
    found = after.truth_set("m1 & ~m0 & K[a] m19")  # a sees m19; m2..m18 are free
    assert len(found) == 2**17 and min(found) == (1 << 18) + 1
    assert after.arrays_bytes() > 0  # no valuation matrix, no partitions were built yet


def test_budget_counts_the_model_arrays_and_the_product_together():
    """12 atoms, 2 agents: the arrays (213 kB) and the product (369 kB) each fit 400 kB,
    together they do not; 1 MB holds both, and the answer is that of explicit worlds."""
    atoms = [f"m{i}" for i in range(12)]
    model = KripkeModel.from_observables(atoms, {"a": atoms[1:], "b": atoms[:1]}, designated=[])
    whisper = ActionModel(
        ["e", "skip"],
        {"e": "m0"},
        {},
        {"a": [("e", "e"), ("skip", "skip")], "b": [("e", "skip"), ("skip", "skip")]},
        "e",
    )
    actions = {"whisper": whisper}
    with pytest.raises(MemoryBudgetError, match="product update with 6,144 worlds"):
        model.holds("[whisper] K[a] m0", actions, memory_budget=400_000)
    assert model.arrays_bytes() > 0  # refused before the arrays were built
    found = model.truth_set("[whisper] B[b] ~m0", actions, memory_budget=1_000_000)
    assert found == _whisper_believed_not_m0(model, {"b": atoms[:1]})


def _whisper_believed_not_m0(model, observes) -> set:
    """Where ``[whisper] B[b] ~m0`` holds, from the definitions, in numpy: the oracle of an
    explicit copy without its 8 million listed pairs. ``b`` tells worlds apart by the atoms
    it observes; it takes ``e`` (pre ``m0``) for ``skip`` (pre true), no postconditions.
    At ``(w, e)``, ``B[b] ~m0`` asks ``~m0`` of every ``(v, skip)`` with ``v ~b w``; the
    announcement holds where ``e`` cannot happen or that does."""
    worlds = list(model.worlds)
    truth = np.array([[a in model.valuation_of(w) for a in model.atoms] for w in worlds])
    seen = truth[:, [model.atoms.index(a) for a in observes["b"]]]
    _, block = np.unique(seen, axis=0, return_inverse=True)
    block = block.ravel()
    m0 = truth[:, model.atoms.index("m0")]
    refuted = np.zeros(block.max() + 1, dtype=bool)  # a block holding a (v, skip) with m0
    np.logical_or.at(refuted, block, m0)
    holds = ~m0 | ~refuted[block]
    return {worlds[i] for i in np.flatnonzero(holds)}


def test_the_analysis_cache_counts_its_nodes_and_is_cleared_over_its_bound(monkeypatch):
    # A running count of the cached nodes (summing every cached table per new formula made
    # the checker slower the more formulas a process had checked).
    from epistemica.del_.explicit import checker

    monkeypatch.setattr(checker, "_ANALYSED_NODES", 10)
    monkeypatch.setattr(checker, "_ANALYSES", {})
    monkeypatch.setattr(checker, "_analysed_count", 0)
    roots = [And(Atom(f"p{i}"), Atom(f"q{i}")) for i in range(4)]  # 3 nodes each
    for root in roots[:3]:
        checker._analyse(root)
    tables = checker._ANALYSES.values()
    assert checker._analysed_count == 9 == sum(len(t) for _, t in tables)
    checker._analyse(roots[0])  # cached: not counted again
    assert checker._analysed_count == 9
    checker._analyse(roots[3])  # 9 + 3 > 10: cleared, then this root's 3 nodes
    assert checker._analysed_count == 3 and list(checker._ANALYSES) == [id(roots[3])]
