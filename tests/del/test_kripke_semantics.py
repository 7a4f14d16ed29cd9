"""The vectorised checker agrees with a textbook reference checker on random models."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import KripkeModel
from epistemica.del_.explicit.relations import Arrows, DenseArrows, Partition

from epistemic_strategies import formulas, models, reference_truth


@settings(max_examples=150)
@given(st.sampled_from(["s5", "kd45", "any", "kd45-s5"]).flatmap(models), formulas())
def test_checker_matches_reference(model, formula):
    assert model.truth_set(formula) == reference_truth(model, formula)


REPRESENTATIONS = {
    "sparse": lambda r: Arrows(r.to_csr()),
    "dense": lambda r: DenseArrows(r.to_dense()),
}


def _forced(model: KripkeModel, representation: str) -> KripkeModel:
    """The same model with every relation forced into one general representation."""
    rel = {a: REPRESENTATIONS[representation](r) for a, r in model.belief_relations.items()}
    return KripkeModel.from_arrays(
        model.lazy_names,
        model.atoms,
        model.valuation,
        model.agents,
        rel,
        dict(rel),
        model.designated_positions,
    )


@settings(max_examples=100)
@given(models("s5"), formulas(), st.sampled_from(sorted(REPRESENTATIONS)))
def test_partition_and_arrows_agree(model, formula, representation):
    assert all(isinstance(r, Partition) for r in model.belief_relations.values())
    forced = _forced(model, representation)
    assert np.array_equal(model.truth_mask(formula), forced.truth_mask(formula))


@settings(max_examples=100)
@given(
    st.sampled_from(["kd45", "any"]).flatmap(models),
    formulas(),
    st.sampled_from(sorted(REPRESENTATIONS)),
)
def test_every_representation_matches_reference(model, formula, representation):
    forced = _forced(model, representation)
    assert forced.truth_set(formula) == reference_truth(model, formula)
    assert forced.is_kd45("a") == model.is_kd45("a")
    assert forced.is_s5("b") == model.is_s5("b")


def test_non_equivalence_is_never_stored_as_partition():
    # Belief that is false at w1: a considers only w2 possible there.
    m = KripkeModel(["w1", "w2"], {"w1": {"p"}}, {"a": [("w1", "w2"), ("w2", "w2")]}, "w1")
    assert not m.is_s5("a") and m.is_kd45("a")
    # An S5 shortcut (class of w1 = {w1, w2}) would make K[a] ~p false at w1.
    assert m.holds("K[a] ~p & p")


def test_common_knowledge_needs_one_step_at_least():
    # w0 -> w1 only: C[a] p at w0 looks at w1 (and beyond), not at w0 itself.
    m = KripkeModel([0, 1], {1: {"p"}}, {"a": [(0, 1), (1, 1)]}, 0)
    assert m.holds("C[a] p & ~p")


def test_distributed_knowledge_is_the_intersection():
    pairs = lambda blocks: [(w, v) for b in blocks for w in b for v in b]  # noqa: E731
    m = KripkeModel(
        ["pq", "p", "q"],
        {"pq": {"p", "q"}, "p": {"p"}, "q": {"q"}},
        {"a": pairs([["pq", "p"], ["q"]]), "b": pairs([["pq", "q"], ["p"]])},
        "pq",
    )
    assert m.holds("D[a, b] (p & q) & ~K[a] q & ~K[b] p")


def test_common_belief_follows_belief_not_knowledge():
    # Sally-Anne in miniature: p is true at w, a cannot tell w from v (knowledge) but
    # believes v (~p) everywhere. Reachable by belief from w: {v} only; by knowledge: {w, v}.
    m = KripkeModel(
        ["w", "v"],
        {"w": {"p"}},
        {"a": [("w", "v"), ("v", "v")], "b": [("w", "v"), ("v", "v")]},
        "w",
        knowledge={"a": [(x, y) for x in "wv" for y in "wv"], "b": [("w", "w"), ("v", "v")]},
    )
    assert m.holds("p & CB[a, b] ~p & EB[a, b] ~p")  # a shared false belief
    assert m.holds("~C[a] ~p & ~E[a, b] ~p & K[b] p")
    assert m.holds("~CB[a, b] p & C[b] p")


def test_common_belief_needs_one_step_and_is_vacuous_without_successors():
    # w0 -> w1 -> w2 (dead end): CB[a] p at w0 looks at w1 and w2, not at w0 itself.
    m = KripkeModel([0, 1, 2], {1: {"p"}, 2: {"p"}}, {"a": [(0, 1), (1, 2)]}, [0, 1, 2])
    assert m.truth_set("CB[a] p") == {0, 1, 2}
    assert m.truth_set("CB[a] false") == {2}
    assert m.truth_set("EB[a] ~p") == {2}
