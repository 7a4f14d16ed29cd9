"""observability_action: events, edges and the laws of the knowledge relation it yields."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import InvalidArgumentError, KripkeModel, observability_action

AGENTS = ["a", "b", "c"]


def coin():
    return KripkeModel.from_observables(
        ["heads", "looking(b)"], {x: ["looking(b)"] for x in AGENTS}, designated=["heads"]
    )


def test_peek_hand_worked():
    # a peeks: a learns heads, b (partial) learns that a knows whether, c is oblivious.
    peek = observability_action(AGENTS, senses="heads", full=["a"], partial=["b"], name="peek")
    after = coin().update(peek)
    assert after.holds("K[a] heads & K[b] Kw[a] heads & ~Kw[b] heads")
    assert after.holds("B[c] ~Kw[a] heads & ~K[c] ~Kw[a] heads & ~K[c] Kw[a] heads")


def test_state_dependent_observability():
    # b sees the peek only if looking; in the actual world b is not looking.
    peek = observability_action(AGENTS, senses="heads", full={"a": True, "b": "looking(b)"})
    after = coin().update(peek)
    assert after.holds("K[a] heads & ~Kw[b] heads & B[b] ~Kw[a] heads")
    looking = KripkeModel.from_observables(
        ["heads", "looking(b)"], {x: ["looking(b)"] for x in AGENTS},
        designated=["heads", "looking(b)"],
    )  # fmt: skip
    assert looking.update(peek).holds("K[b] heads & B[c] ~Kw[b] heads")


def test_announcement_partial_observers_learn_only_that_it_was_said_or_denied():
    m = coin()
    say = observability_action(AGENTS, announces="heads", full=["a", "b"], partial=["c"])
    assert [e for e in say.events] == ["action", "action[~]"]
    after = m.update(say)
    assert after.holds("K[a] heads & K[b] heads & ~Kw[c] heads & K[c] Kw[b] heads")


def test_ontic_change_oblivious_keeps_old_belief():
    open_ = observability_action(AGENTS, effects={"opened": True}, full=["a"])
    after = coin().update(open_)
    assert after.holds("opened & K[a] opened & B[b] ~opened & ~K[b] ~opened & ~K[b] opened")


def test_executable_is_not_learnt_by_observers():
    # c misses the sensing, then hears a announce heads: with the precondition inside the
    # events c's beliefs collapse (it believes everything); with executability it learns.
    sense = observability_action(AGENTS, senses="heads", full=["a"])
    inside = observability_action(AGENTS, pre="B[a] heads", announces="heads", full=AGENTS)
    outside = observability_action(AGENTS, announces="heads", executable="B[a] heads", full=AGENTS)
    m = coin().update(sense)
    assert m.update(inside).holds("B[c] false")
    assert m.update(outside).holds("B[c] heads & ~B[c] false & B[b] heads")
    assert not coin().applicable_in_some(outside)  # a does not believe heads before sensing


@pytest.mark.parametrize(
    "kwargs",
    [
        {"agents": []},
        {"agents": ["a", "a"]},
        {"agents": AGENTS, "full": ["z"]},
        {"agents": AGENTS, "partial": {"a": 3}},
        {"agents": AGENTS, "senses": "p", "announces": "p"},
        {"agents": AGENTS, "effects": ["p"]},
        {"agents": AGENTS, "senses": []},
        {"agents": AGENTS, "name": ""},
    ],
)
def test_bad_arguments_raise(kwargs):
    with pytest.raises(InvalidArgumentError):
        observability_action(**kwargs)


# Conditions over atoms every agent observes: each agent knows its own observability.
CONDITIONS = st.sampled_from([True, False, "looking(b)", "~looking(b)"])


@st.composite
def actions(draw):
    kind = draw(st.sampled_from(["ontic", "sense", "announce"]))
    full = {x: draw(CONDITIONS) for x in AGENTS if draw(st.booleans())}
    partial = {x: draw(CONDITIONS) for x in AGENTS if draw(st.booleans())}
    kwargs = {"full": full, "partial": partial}
    if kind == "ontic":
        kwargs["effects"] = {"heads": draw(st.sampled_from(["~heads", "true", "heads"]))}
    elif kind == "sense":
        kwargs["senses"] = "heads"
    else:
        kwargs["announces"] = draw(st.sampled_from(["heads", "true"]))
    return observability_action(AGENTS, **kwargs)


@settings(max_examples=40)
@given(st.lists(actions(), min_size=1, max_size=3), st.booleans())
def test_knowledge_stays_an_equivalence_containing_belief(steps, heads):
    m = KripkeModel.from_observables(
        ["heads", "looking(b)"], {x: ["looking(b)"] for x in AGENTS},
        designated=["heads"] if heads else [],
    )  # fmt: skip
    for act in steps:
        if not m.applicable_in_some(act):
            return
        m = m.update(act)
        for agent in AGENTS:
            assert m.is_s5(agent, relation="knowledge")
            for w in m.worlds:
                believed = set(m.successors(agent, w))
                assert believed <= set(m.successors(agent, w, relation="knowledge"))
