"""RowTruth: propositional truth remembered per valuation row gives the evaluator's answer
on every model it meets, and product updates through it are the same models."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import KripkeModel, observability_action
from epistemica.del_.explicit.action import product_update
from epistemica.del_.explicit.row_truth import RowTruth
from tests.epistemic_strategies import formulas, models, reference_truth

# Random formulas over every node kind: the modal ones go to the evaluator.
FORMULAS = formulas(agents=("a",), max_leaves=10, announcements=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(models(kind="kd45", max_worlds=5), min_size=1, max_size=4), FORMULAS)
def test_agrees_with_the_reference_on_every_model_of_a_sequence(ms, formula):
    # One RowTruth across several models: values remembered from one model answer the
    # next; each answer must be the reference checker's set (modal formulas included).
    rows = RowTruth()
    for m in ms:
        expected = reference_truth(m, formula)
        got = rows(m, formula)
        assert {w for w, ok in zip(m.worlds, got.tolist(), strict=True) if ok} == expected


def test_counts_one_entry_per_combination_of_the_formulas_atoms():
    m = KripkeModel(
        ["u", "v", "w", "x"],
        {"u": {"p"}, "v": {"p", "q"}, "w": {"p", "r"}, "x": {"r"}},
        {"a": [("u", "u")]},
        ["u"],
    )
    rows = RowTruth()
    assert rows(m, "p | q").tolist() == [True, True, True, False]
    # (p, q) combinations met: (1,0) at u and w, (1,1) at v, (0,0) at x
    assert rows.entries == 3
    again = rows(m, "p | q")
    assert again.tolist() == [True, True, True, False] and rows.entries == 3
    assert rows(m, "K[a] p").tolist() == m.truth_mask("K[a] p").tolist()
    assert rows.entries == 3  # a modal formula is not remembered


def test_forgets_everything_past_its_limit_and_stays_right():
    m = KripkeModel(["u", "v", "w"], {"u": {"p"}, "v": {"q"}}, {"a": []}, ["u"])
    rows = RowTruth(max_entries=4)
    for text in ["p", "q", "p & q", "p | q", "~p"]:
        assert rows(m, text).tolist() == m.truth_mask(text).tolist()
        assert rows.entries <= 4


def _same_model(x: KripkeModel, y: KripkeModel) -> bool:
    return (
        x.worlds == y.worlds
        and x.atoms == y.atoms
        and (x.valuation == y.valuation).all()
        and list(x.designated) == list(y.designated)
        and all(
            {(w, v) for w in x.worlds for v in x.successors(a, w)}
            == {(w, v) for w in y.worlds for v in y.successors(a, w)}
            for a in x.agents
        )
    )


@settings(max_examples=40, deadline=None)
@given(models(kind="kd45", max_worlds=5), st.sampled_from(["p", "q", "r"]))
def test_product_update_through_rows_is_the_same_model(m, atom):
    act = observability_action(
        ["a", "b"],
        pre="q | ~r",
        effects={atom: "p | ~q", "r": "q & r"},
        senses="q",
        full={"a": "p"},  # conditioned edges: a observes only where p holds
        partial={"b": "~p"},
    )
    if not m.applicable_in_some(act):
        return
    rows = RowTruth()
    plain = product_update(m, act)
    remembered = product_update(m, act, rows=rows)
    assert _same_model(plain, remembered)
    twice = product_update(m, act, rows=rows)  # now from remembered values only
    assert _same_model(plain, twice)
