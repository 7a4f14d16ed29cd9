"""The KripkeModel and ActionModel API: construction errors, inspection, export."""

from __future__ import annotations

import networkx as nx
import numpy as np
import pytest

from epistemica.del_ import (
    ActionModel,
    InvalidArgumentError,
    KnowledgeStructure,
    KripkeModel,
    ModelError,
    private_announcement,
    product_update,
    public_announcement,
)
from epistemica.del_.planning.planner import applicable_in_all

PAIRS = [("u", "u"), ("u", "v"), ("v", "u"), ("v", "v")]


def two_worlds(**kwargs):
    return KripkeModel(
        ["u", "v"], {"u": {"p"}}, {"a": PAIRS, "b": [("u", "u"), ("v", "v")]}, "u", **kwargs
    )


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((["u", "u"], {}, {"a": []}, "u"), "distinct"),
        ((["u"], {"x": {"p"}}, {"a": []}, "u"), "unknown world 'x' in valuation"),
        ((["u"], {}, {"a": [("u", "x")]}, "u"), "unknown world 'x' in relation of a"),
        ((["u"], {}, {"a": []}, "x"), "unknown world 'x' in designated"),
        ((["u"], {}, {"a": []}, []), "at least one designated"),
    ],
)
def test_malformed_models_are_refused(args, message):
    with pytest.raises(ModelError, match=message):
        KripkeModel(*args)


def test_knowledge_for_unknown_agent_is_refused():
    with pytest.raises(ModelError, match="unknown agent 'z'"):
        two_worlds(knowledge={"z": []})


def test_inspection():
    m = two_worlds()
    assert m.agents == ("a", "b") and m.atoms == ("p",) and m.n_worlds == 2
    assert m.designated == ("u",)
    assert m.valuation_of("u") == {"p"} and m.valuation_of("v") == frozenset()
    assert set(m.successors("a", "u")) == {"u", "v"} and m.successors("b", "u") == ("u",)
    assert m.is_s5("a") and m.is_kd45("a") and not m.has_separate_knowledge()
    with pytest.raises(InvalidArgumentError, match="unknown agent 'z'"):
        m.is_s5("z")
    with pytest.raises(InvalidArgumentError, match="'belief' or 'knowledge'"):
        m.is_s5("a", relation="trust")
    with pytest.raises(ModelError, match="unknown world 'w'"):
        m.valuation_of("w")


def test_predicate_atoms_are_canonical():
    m = KripkeModel(["w"], {"w": {"at(r1,g1)"}}, {"a": [("w", "w")]}, "w")
    assert m.atoms == ("at(r1, g1)",)
    assert m.holds("at(r1, g1) & K[a] at( r1 , g1 )")


def test_unknown_agent_in_formula_names_the_agents():
    with pytest.raises(InvalidArgumentError, match="the model's agents: a, b"):
        two_worlds().holds("K[c] p")


def test_announcement_of_a_false_formula_is_refused():
    with pytest.raises(InvalidArgumentError, match="false at every designated world"):
        two_worlds().announce("~p")


def test_inapplicable_update_is_refused():
    m = two_worlds()
    assert not m.applicable_in_some(public_announcement("~p", m.agents))
    with pytest.raises(InvalidArgumentError, match="not executable"):
        m.update(public_announcement("~p", m.agents))


def test_action_agents_must_match():
    with pytest.raises(ModelError, match="same agents"):
        two_worlds().update(public_announcement("p", ["a"]))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"events": ["e", "e"]}, "distinct"),
        ({"pre": {"x": "p"}}, "unknown event 'x' in pre"),
        ({"relations": {"a": [("e", "x")]}}, "unknown event 'x'"),
        ({"relations": {"a": [("e",)]}}, "must be"),
        ({"designated": []}, "at least one designated"),
        ({"knowledge": {"z": []}}, "unknown agent 'z'"),
    ],
)
def test_malformed_action_models_are_refused(kwargs, message):
    args = {
        "events": ["e"],
        "pre": {},
        "post": {},
        "relations": {"a": [("e", "e")]},
        "designated": "e",
        **kwargs,
    }
    with pytest.raises(ModelError, match=message):
        ActionModel(**args)


def test_update_names_worlds_by_world_and_event():
    m = two_worlds().update(private_announcement("p", ["b"], ["a", "b"]))
    assert set(m.worlds) == {("u", "announce"), ("u", "skip"), ("v", "skip")}
    assert m.designated == (("u", "announce"),)
    assert m.has_separate_knowledge()


def test_factual_change_reads_the_old_valuation():
    swap = ActionModel(["s"], {}, {"s": {"p": "q", "q": "p"}}, {"a": [("s", "s")]}, "s")
    m = KripkeModel(["w"], {"w": {"p"}}, {"a": [("w", "w")]}, "w", atoms=["p", "q"])
    assert m.update(swap).holds("q & ~p")


def test_to_networkx():
    g = two_worlds().to_networkx()
    assert isinstance(g, nx.MultiDiGraph)
    assert dict(g.nodes(data=True)) == {
        "u": {"atoms": ["p"], "designated": True},
        "v": {"atoms": [], "designated": False},
    }
    edges = sorted((w, v, d["agent"]) for w, v, d in g.edges(data=True))
    assert edges == sorted([(w, v, "a") for w, v in PAIRS] + [("u", "u", "b"), ("v", "v", "b")])


def test_to_networkx_adds_separate_knowledge_edges():
    m = two_worlds().update(private_announcement("p", ["b"], ["a", "b"]))
    kinds = {d["relation"] for _, _, d in m.to_networkx().edges(data=True) if d["agent"] == "a"}
    assert kinds == {"belief", "knowledge"}


def test_to_dot():
    dot = two_worlds().to_dot()
    assert dot.startswith("digraph kripke {") and dot.endswith("}")
    assert dot.count("doublecircle") == 1 and dot.count("->") == 6
    assert '[label="a"]' in dot


def test_truth_mask_is_a_copy():
    m = two_worlds()
    mask = m.truth_mask("p")
    mask[:] = False
    assert m.truth_mask("p").tolist() == [True, False]
    assert np.array_equal(m.truth_mask("K[b] p"), [True, False])


def test_repoint_shares_truth_sets():
    m = two_worlds()
    other = m.repoint("v")
    assert other.designated == ("v",) and not other.holds("p") and m.holds("p")
    with pytest.raises(ModelError, match="unknown world"):
        m.repoint("w")


def test_every_derived_model_keeps_the_public_class():
    """Algorithms build ``type(model)``: what they return still has the convenience methods."""
    m = KripkeModel.from_observables(["p", "q"], {"a": ["p"], "b": []}, designated=["p"])
    act = private_announcement("p", ["b"], ["a", "b"])
    derived = {
        "announce": m.announce("p"),
        "update": m.update(act),
        "product_update": product_update(m, act),
        "minimize": m.minimize(),
        "restrict": m.restrict(np.ones(m.n_worlds, dtype=bool)),
        "repoint": m.repoint(m.worlds),
        "to_kripke": m.to_symbolic().to_kripke(),
        "explicit announce": two_worlds().announce("p"),
    }
    for name, model in derived.items():
        assert type(model) is KripkeModel, name
    s = m.to_symbolic()
    assert type(s) is KnowledgeStructure
    assert type(s.announce("p")) is KnowledgeStructure
    assert type(s.update(act)) is KnowledgeStructure


def test_applicable_in_some_is_not_applicable_in_all():
    """Two designated worlds, p and ~p: announcing p works at one of them, not at both."""
    both = KripkeModel.from_observables(["p"], {"a": []})
    announce_p = public_announcement("p", ["a"])
    assert both.applicable_in_some(announce_p)
    assert not applicable_in_all(both, announce_p)
    assert [world for world, _ in both.update(announce_p).designated] == [1]  # p = code 1
