"""Worked examples with published answers: muddy children, Sally-Anne, coin toss, Moore."""

from __future__ import annotations

import itertools

import pytest

from epistemica.del_ import (
    ActionModel,
    Atom,
    KnowWhether,
    KripkeModel,
    Not,
    conjunction,
    disjunction,
    public_announcement,
    public_assignment,
    semi_private_sensing,
)


def muddy_children(n, muddy):
    atoms = [f"m{i}" for i in range(1, n + 1)]
    observes = {f"c{i}": [a for a in atoms if a != f"m{i}"] for i in range(1, n + 1)}
    return KripkeModel.from_observables(atoms, observes, designated=[f"m{i}" for i in muddy])


def nobody_knows(n):
    return conjunction(Not(KnowWhether(f"c{i}", Atom(f"m{i}"))) for i in range(1, n + 1))


def at_least_one(n):
    return disjunction(Atom(f"m{i}") for i in range(1, n + 1))


@pytest.mark.parametrize("n", [3, 4])
def test_surviving_worlds_after_r_rounds(n):
    """After the father and r rounds of "nobody knows", the worlds with >= r+1 muddy remain."""
    model = muddy_children(n, muddy=range(1, n + 1)).announce(at_least_one(n))
    for rounds in range(n):
        survivors = {model.valuation_of(w) for w in model.worlds}
        expected = {
            frozenset(f"m{i}" for i in muddy)
            for k in range(rounds + 1, n + 1)
            for muddy in itertools.combinations(range(1, n + 1), k)
        }
        assert survivors == expected
        if rounds < n - 1:
            model = model.announce(nobody_knows(n))


@pytest.mark.parametrize(("n", "m"), [(n, m) for n in (3, 4) for m in range(1, n + 1)])
def test_muddy_children_know_after_m_minus_one_rounds(n, m):
    muddy = range(1, m + 1)
    they_know = conjunction(KnowWhether(f"c{i}", Atom(f"m{i}")) for i in muddy)
    model = muddy_children(n, muddy).announce(at_least_one(n))
    for _ in range(m - 1):
        assert not model.holds(they_know)
        assert model.holds(nobody_knows(n))
        model = model.announce(nobody_knows(n))
    assert model.holds(they_know)
    # The clean children learn their state one round later, never earlier.
    if m < n:
        assert not model.holds(KnowWhether(f"c{n}", Atom(f"m{n}")))
        assert model.announce(they_know).holds(KnowWhether(f"c{n}", Atom(f"m{n}")))


def test_muddy_children_without_the_father_learn_nothing():
    model = muddy_children(3, [1, 2])
    for _ in range(3):
        assert model.holds(nobody_knows(3))
        assert model.announce(nobody_knows(3)).n_worlds == model.n_worlds


def sally_anne():
    agents = ["sally", "anne"]
    start = KripkeModel(
        ["w"], {"w": {"basket", "sally_here"}}, {a: [("w", "w")] for a in agents}, "w"
    )
    leaves = public_assignment({"sally_here": "false"}, agents)
    # Anne moves the marble; Sally, away, believes nothing happened.
    move = ActionModel(
        ["move", "skip"],
        pre={"move": "~sally_here & basket"},
        post={"move": {"basket": "false", "box": "true"}},
        relations={
            "anne": [("move", "move"), ("skip", "skip")],
            "sally": [("move", "skip"), ("skip", "skip")],
        },
        designated="move",
        knowledge={
            "anne": [("move", "move"), ("skip", "skip")],
            "sally": [(e, f) for e in ("move", "skip") for f in ("move", "skip")],
        },
    )
    returns = public_assignment({"sally_here": "true"}, agents)
    return start.update(leaves).update(move).update(returns)


def test_sally_anne_false_belief():
    m = sally_anne()
    assert m.holds("box & ~basket & sally_here")
    assert m.holds("B[sally] basket")  # Sally believes the marble is in the basket ...
    assert m.holds("~K[sally] basket")  # ... which is belief, not knowledge
    assert m.holds("K[anne] B[sally] basket")  # Anne knows Sally's false belief
    assert m.holds("K[anne] box & ~B[sally] box")
    assert not m.is_s5("sally") and m.is_kd45("sally")
    assert m.is_s5("sally", relation="knowledge")


def test_coin_toss_shown_to_b_only():
    agents = ["a", "b"]
    m = KripkeModel.from_observables(["heads"], {"a": [], "b": []}, designated=["heads"])
    m = m.update(semi_private_sensing("heads", ["b"], agents))
    assert m.holds("Kw[b] heads & ~Kw[a] heads & K[a] Kw[b] heads")
    assert m.holds("K[b] heads & ~K[a] heads & ~K[a] ~heads")
    assert m.holds("C[a, b] Kw[b] heads")


def test_moore_sentence_is_unsuccessful():
    m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    moore = "p & ~K[a] p"
    assert m.holds(moore)
    assert not m.announce(moore).holds(moore)
    assert m.holds("[!p & ~K[a] p] K[a] p")
    assert m.update(public_announcement(moore, ["a"])).holds("K[a] p")
