"""The symbolic backend (knowledge structures on BDDs) against the explicit one.

Hand-worked examples first; then property tests: on random Kripke models, random formulas
with every operator and random action models, both backends give the same truth values
and the same truth sets (world by world); finally every shipped spec's claims.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from epistemica.del_ import (
    ActionModel,
    After,
    InvalidArgumentError,
    KnowledgeStructure,
    KripkeModel,
    ModelError,
    load_spec,
    plan,
    private_announcement,
    public_announcement,
    semi_private_sensing,
)

from epistemic_strategies import AGENTS, ATOMS, formulas, models

# DEL spec files; mission files (specs/*.epi, specs/stress/) are tested in tests/mission.
SPECS = sorted(
    p
    for p in Path(__file__).resolve().parents[2].glob("specs/**/*.epi")
    if p.parent.name in ("planning", "puzzles")
)
PLANNING = [p for p in SPECS if p.parent.name == "planning"]

MUDDY = {"c1": ["m2", "m3"], "c2": ["m1", "m3"], "c3": ["m1", "m2"]}
NOBODY_KNOWS = "~Kw[c1] m1 & ~Kw[c2] m2 & ~Kw[c3] m3"
ALL_KNOW = "K[c1] m1 & K[c2] m2 & K[c3] m3"


# -- hand-worked examples ----------------------------------------------------------------


def test_muddy_children_three_rounds():
    # Fagin et al. 1995, section 1.1: with 3 muddy children, everyone knows in round 3.
    s = KnowledgeStructure.from_observables(["m1", "m2", "m3"], MUDDY, designated=MUDDY["c1"])
    assert s.n_worlds == 8
    s = s.announce("m1 | m2 | m3")
    assert s.n_worlds == 7
    assert s.holds(NOBODY_KNOWS)
    s = s.announce(NOBODY_KNOWS)  # only m2 & m3 are muddy: they know now
    assert s.n_worlds == 4  # the worlds with at least two muddy children
    assert s.holds("K[c2] m2 & K[c3] m3 & ~Kw[c1] m1")


def test_hundred_children_common_knowledge_needs_the_father():
    atoms = [f"m{i}" for i in range(1, 101)]
    observes = {f"c{i}": atoms[: i - 1] + atoms[i:] for i in range(1, 101)}
    s = KnowledgeStructure.from_observables(atoms, observes, designated=atoms)
    some, everyone = " | ".join(atoms), ", ".join(observes)
    assert s.n_worlds == 2**100
    # Reaching the clean world takes all 100 children; two of them keep m3..m100 fixed.
    assert s.holds(f"E[{everyone}] ({some}) & ~C[{everyone}] ({some}) & C[c1, c2] ({some})")
    assert s.holds(f"[!{some}] C[{everyone}] ({some})")
    assert s.announce(some).n_worlds == 2**100 - 1


def test_private_announcement_gives_a_false_belief():
    s = KnowledgeStructure.from_observables(["p"], {"a": [], "b": []}, designated=[])
    act = private_announcement("~p", ["a"], ["a", "b"])
    after = s.update(act)
    assert after.has_separate_knowledge()
    assert after.holds("K[a] ~p & ~Kw[b] p & B[b] ~K[a] ~p & ~K[b] ~K[a] ~p")


def test_postconditions_change_facts_and_keep_the_old_knowledge():
    s = KnowledgeStructure.from_observables(["p", "q"], {"a": ["p"], "b": []}, designated=["p"])
    flip = ActionModel(["e"], {}, {"e": {"p": "~p", "q": "p"}}, {"a": [("e", "e")],
                       "b": [("e", "e")]}, "e")  # fmt: skip
    after = s.update(flip)
    assert after.holds("~p & q & K[a] (~p & q) & ~Kw[b] q")
    assert s.holds("[flip] (q & K[a] q)", actions={"flip": flip})


def test_undeclared_atom_is_an_error_with_a_suggestion():
    s = KnowledgeStructure.from_observables(["muddy"], {"a": []})
    with pytest.raises(InvalidArgumentError, match="unknown atom 'mudy'") as err:
        s.holds("K[a] mudy")
    assert "did you mean 'muddy'" in err.value.hint
    with pytest.raises(InvalidArgumentError, match="unknown agent"):
        s.holds("K[z] muddy")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"law": "p & ~p"}, "no valuation satisfies the law"),
        ({"law": "p", "designated": []}, "designated valuation violates the law"),
        ({"law": "K[a] p"}, "propositional"),
        ({"designated": ["x"]}, "unknown atom 'x'"),
    ],
)
def test_bad_constructions_are_refused(kwargs, message):
    with pytest.raises(InvalidArgumentError, match=message):
        KnowledgeStructure.from_observables(["p"], {"a": []}, **kwargs)


def test_unexecutable_action_and_false_announcement_are_refused():
    s = KnowledgeStructure.from_observables(["p"], {"a": []}, designated=[])
    with pytest.raises(InvalidArgumentError, match="cannot announce p"):
        s.announce("p")
    assert not s.applicable_in_some(public_announcement("p", ["a"]))
    with pytest.raises(InvalidArgumentError, match="not executable"):
        s.update(public_announcement("p", ["a"]))
    with pytest.raises(ModelError, match="same agents"):
        s.update(public_announcement("p", ["a", "b"]))
    with pytest.raises(InvalidArgumentError, match="unknown action"):
        s.holds("[go] p")


def test_to_kripke_refuses_a_huge_structure():
    atoms = [f"p{i}" for i in range(40)]
    s = KnowledgeStructure.from_observables(atoms, {"a": atoms})
    with pytest.raises(InvalidArgumentError, match="more than 2048 worlds"):
        s.to_kripke()


# -- property tests ----------------------------------------------------------------------

ANY_MODEL = st.sampled_from(["s5", "kd45", "any", "kd45-s5"]).flatmap(
    lambda kind: models(kind, max_worlds=5)
)
FORMULAS = formulas(max_leaves=10)


@settings(max_examples=600)
@given(ANY_MODEL, FORMULAS)
def test_same_truth_value(model, f):
    s = model.to_symbolic(ATOMS)
    assert s.holds(f) == model.holds(f)
    assert s.count_designated(f) == sum(w in model.truth_set(f) for w in model.designated)


@settings(max_examples=250)
@given(ANY_MODEL, FORMULAS)
def test_same_truth_set_and_count(model, f):
    truth = model.truth_set(f)
    s = model.to_symbolic(ATOMS)
    assert s.n_worlds == model.n_worlds
    assert s.count(f) == len(truth)
    for w in model.worlds:
        assert model.repoint(w).to_symbolic(ATOMS).holds(f) == (w in truth)


@settings(max_examples=200)
@given(ANY_MODEL)
def test_round_trip_through_kripke_keeps_every_truth_value(model):
    back = model.to_symbolic(ATOMS).to_kripke()
    assert back.n_worlds == model.n_worlds
    for f in ["p", "K[a] p", "B[b] ~q", "C[a, b] (p | q)", "CB[a, b] r", "D[a, b] p"]:
        assert back.holds(f) == model.holds(f)


PROPOSITIONAL = formulas(max_leaves=3, agents=("a",)).filter(lambda f: f.modal_depth() == 0)
SMALL = formulas(max_leaves=4, announcements=False)


@st.composite
def action_models(draw):
    """A random action model: 1-3 events, epistemic preconditions, factual change,
    arbitrary or equivalence event relations, conditioned edges, separate knowledge."""
    n = draw(st.integers(1, 3))
    events = list(range(n))
    pre = {e: draw(SMALL) for e in events if draw(st.booleans())}
    post = {}
    for e in events:
        changed = draw(st.lists(st.sampled_from(ATOMS), unique=True, max_size=2))
        post[e] = {a: draw(PROPOSITIONAL) for a in changed}

    def edges():
        if draw(st.booleans()):
            labels = draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))
            return [(e, f) for e in events for f in events if labels[e] == labels[f]]
        pairs = draw(st.lists(st.tuples(st.sampled_from(events), st.sampled_from(events))))
        return [(e, f, draw(PROPOSITIONAL)) if draw(st.booleans()) else (e, f) for e, f in pairs]

    relations = {a: edges() for a in AGENTS}
    knowledge = {a: edges() for a in AGENTS if draw(st.booleans())}
    designated = draw(st.lists(st.sampled_from(events), min_size=1, unique=True))
    return ActionModel(events, pre, post, relations, designated, knowledge)


@st.composite
def observables(draw):
    """Arguments of ``from_observables`` (a law that some valuation satisfies)."""
    observes = {a: draw(st.lists(st.sampled_from(ATOMS), unique=True)) for a in AGENTS}
    law = draw(PROPOSITIONAL)
    kripke = _or_none(lambda: KripkeModel.from_observables(ATOMS, observes, law=law))
    assume(kripke is not None)
    code = draw(st.sampled_from(kripke.worlds))
    designated = [a for j, a in enumerate(ATOMS) if code >> (len(ATOMS) - 1 - j) & 1]
    return observes, law, designated


def observable_models():
    return observables().map(
        lambda args: KripkeModel.from_observables(ATOMS, args[0], law=args[1], designated=args[2])
    )


def _or_none(build):
    try:
        return build()
    except InvalidArgumentError:
        return None


ACTION_MODELS = st.one_of(ANY_MODEL, observable_models())


@settings(max_examples=350)
@given(ACTION_MODELS, action_models(), formulas(max_leaves=6, actions=["act"]))
def test_same_truth_after_random_action_models(model, action, f):
    actions = {"act": action}
    s = model.to_symbolic(ATOMS)
    assert s.holds(After("act", f), actions) == model.holds(After("act", f), actions)
    assert s.holds(f, actions) == model.holds(f, actions)
    assert s.applicable_in_some(action) == model.applicable_in_some(action)
    if model.applicable_in_some(action):
        after, symbolic_after = model.update(action), s.update(action)
        assert symbolic_after.n_worlds == after.n_worlds
        assert symbolic_after.holds(f, actions) == after.holds(f, actions)
        assert symbolic_after.count(f, actions) == len(after.truth_set(f, actions))


@settings(max_examples=200)
@given(observables(), action_models(), formulas(max_leaves=8, actions=["act"]))
def test_from_observables_agrees_with_the_kripke_construction(args, action, f):
    observes, law, designated = args
    s = KnowledgeStructure.from_observables(ATOMS, observes, law=law, designated=designated)
    model = KripkeModel.from_observables(ATOMS, observes, law=law, designated=designated)
    assert s.n_worlds == model.n_worlds
    assert s.holds(f, {"act": action}) == model.holds(f, {"act": action})
    assert s.count(f, {"act": action}) == len(model.truth_set(f, {"act": action}))


@settings(max_examples=150)
@given(observable_models(), st.lists(st.sampled_from(["sense", "private", "public"]), max_size=3))
def test_observable_structures_stay_observational_under_s5_actions(model, steps):
    s = model.to_symbolic(ATOMS)
    for step in steps:
        act = {
            "sense": semi_private_sensing("p", ["a"], AGENTS),
            "private": private_announcement("q | r", ["b"], AGENTS),
            "public": public_announcement("~K[a] r", AGENTS),
        }[step]
        if not model.applicable_in_some(act):
            return
        model, s = model.update(act), s.update(act)
        for f in ["K[a] p", "B[b] (q | r)", "C[a, b] ~r", "CB[a, b] q", "D[a, b] r"]:
            assert s.holds(f) == model.holds(f)


# -- shipped specs -----------------------------------------------------------------------


# The generated puzzles (tens of kB and more) are beyond the explicit backend.
BOTH_BACKENDS = [p for p in SPECS if p.stat().st_size < 20_000]


@pytest.mark.parametrize("path", BOTH_BACKENDS, ids=[p.name for p in BOTH_BACKENDS])
def test_shipped_specs_give_the_same_answers(path):
    spec = load_spec(path, backend="explicit")
    s = spec.model.to_symbolic(spec.atoms)
    for check in spec.checks:
        assert s.holds(check.formula, spec.actions) == spec.holds(check.formula), check.name
    if spec.goal is None:
        return
    assert s.holds(spec.goal, spec.actions) == spec.holds(spec.goal)
    # Every action once from the initial state: the same applicability, size and goal.
    for name, action in spec.actions.items():
        assert s.applicable_in_some(action) == spec.model.applicable_in_some(action), name
        if spec.model.applicable_in_some(action):
            after, symbolic_after = spec.model.update(action), s.update(action)
            assert symbolic_after.n_worlds == after.n_worlds, name
            assert symbolic_after.holds(spec.goal) == after.holds(spec.goal), name


@pytest.mark.parametrize("path", PLANNING, ids=[p.name for p in PLANNING])
def test_explicit_plans_work_step_by_step_on_the_symbolic_backend(path):
    spec = load_spec(path)
    steps = plan(spec.model, spec.actions, spec.goal)
    assert steps is not None
    model, s = spec.model, spec.model.to_symbolic(spec.atoms)
    for name in steps:
        assert s.holds(spec.goal) == model.holds(spec.goal), name
        model, s = model.update(spec.actions[name]), s.update(spec.actions[name])
        assert s.n_worlds == model.n_worlds, name
    assert s.holds(spec.goal)
