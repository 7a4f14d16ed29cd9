"""Bisimulation contraction and canonical keys against a naive reference.

The reference below is the textbook definition run to a fixed point on Python sets: start
from "same valuation", split by the set of blocks each world reaches per agent and
relation, until nothing splits. It shares no code with epistemica's refinement
(``del/explicit/_refinement.py``, incremental and vectorised), so agreement between the
two is evidence that both compute the coarsest bisimulation.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import KripkeModel, bisimilar, bisimulation_classes
from epistemica.del_.explicit._refinement import coarsest_partition
from epistemica.del_.explicit.bisimulation import generated_submodel
from epistemica.del_.explicit.canonical import canonical_classes, canonical_key
from tests.epistemic_strategies import models

KINDS = st.sampled_from(["s5", "kd45", "any", "kd45-s5"])


def reference_classes(model) -> list[int]:
    """Coarsest bisimulation by naive refinement: a class number per world, in order."""
    worlds = list(model.worlds)
    successors = [
        {w: frozenset(model.successors(a, w, relation=kind)) for w in worlds}
        for a in model.agents
        for kind in ("belief", "knowledge")
    ]
    label = {w: frozenset(model.valuation_of(w)) for w in worlds}
    while True:
        refined = {
            w: (label[w], tuple(frozenset(label[v] for v in succ[w]) for succ in successors))
            for w in worlds
        }
        if len(set(refined.values())) == len(set(label.values())):
            break
        label = refined
    names: dict = {}
    return [names.setdefault(label[w], len(names)) for w in worlds]


def same_partition(first, second) -> bool:
    pairs = set(zip(list(first), list(second), strict=True))
    return len(pairs) == len(set(first)) == len(set(second))


def reference_generated(model) -> set:
    reached = set(model.designated)
    frontier = list(reached)
    while frontier:
        w = frontier.pop()
        for a in model.agents:
            for kind in ("belief", "knowledge"):
                for v in model.successors(a, w, relation=kind):
                    if v not in reached:
                        reached.add(v)
                        frontier.append(v)
    return reached


def permuted(model, rng_seed: int):
    """The same model with its worlds renamed and listed in another order."""
    rng = np.random.default_rng(rng_seed)
    worlds = list(model.worlds)
    order = rng.permutation(len(worlds))
    rename = {w: f"x{i}" for i, w in enumerate(rng.permutation(len(worlds)).tolist())}
    rename = {w: rename[i] for i, w in enumerate(worlds)}
    new_worlds = [rename[worlds[i]] for i in order]
    relations = {
        a: [(rename[w], rename[v]) for w in worlds for v in model.successors(a, w)]
        for a in model.agents
    }
    knowledge = {
        a: [
            (rename[w], rename[v])
            for w in worlds
            for v in model.successors(a, w, relation="knowledge")
        ]
        for a in model.agents
    }
    return KripkeModel(
        new_worlds,
        {rename[w]: model.valuation_of(w) for w in worlds},
        relations,
        [rename[w] for w in model.designated],
        knowledge=knowledge,
    )


@settings(max_examples=150, deadline=None)
@given(KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=8)))
def test_classes_agree_with_the_reference(model):
    assert same_partition(bisimulation_classes(model), reference_classes(model))


@settings(max_examples=100, deadline=None)
@given(KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=8)))
def test_generated_submodel_is_what_the_designated_worlds_reach(model):
    from epistemica.del_.explicit import bisimulation

    assert set(generated_submodel(model).worlds) == reference_generated(model)
    saved = bisimulation._STEPS
    try:  # the breadth-first search over the explicit graph, forced
        bisimulation._STEPS = 0
        assert set(generated_submodel(model).worlds) == reference_generated(model)
    finally:
        bisimulation._STEPS = saved


@settings(max_examples=100, deadline=None)
@given(KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=8)))
def test_minimize_is_bisimilar_and_minimal(model):
    small = model.minimize()
    assert bisimilar(model, small)
    # minimal: no two of its worlds are bisimilar (by the reference)
    assert len(set(reference_classes(small))) == small.n_worlds
    assert set(small.worlds) <= reference_generated(model)


@settings(max_examples=100, deadline=None)
@given(
    KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=7)),
    st.integers(0, 2**32 - 1),
)
def test_invariant_under_renaming_and_permutation(model, seed):
    other = permuted(model, seed)
    assert bisimilar(model, other)
    assert same_partition(
        bisimulation_classes(model),
        [bisimulation_classes(other)[other.worlds.index(w)] for w in _renamed(model, other)],
    )
    assert canonical_key(generated_submodel(model)) == canonical_key(generated_submodel(other))
    assert canonical_key(model.minimize()) == canonical_key(other.minimize())


def _renamed(model, other):
    """The world of ``other`` matching each world of ``model`` (same position before
    the permutation: recovered through the relation-preserving renaming)."""
    # permuted() keeps valuations and relations; the names map back through the classes of
    # the disjoint union, so match worlds by the reference on the pair.
    union = _union(model, other)
    classes = reference_classes(union)
    first = {w: classes[i] for i, w in enumerate(union.worlds)}
    found = []
    for w in model.worlds:
        match = next(v for v in other.worlds if first[("o", v)] == first[("m", w)])
        found.append(match)
    return found


def _union(model, other):
    worlds = [("m", w) for w in model.worlds] + [("o", w) for w in other.worlds]
    valuation = {("m", w): model.valuation_of(w) for w in model.worlds}
    valuation.update({("o", w): other.valuation_of(w) for w in other.worlds})

    def pairs(kind):
        return {
            a: [(("m", w), ("m", v)) for w in model.worlds for v in model.successors(a, w, kind)]
            + [(("o", w), ("o", v)) for w in other.worlds for v in other.successors(a, w, kind)]
            for a in model.agents
        }

    return KripkeModel(worlds, valuation, pairs("belief"), worlds[:1], knowledge=pairs("knowledge"))


@settings(max_examples=150, deadline=None)
@given(
    KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=6)),
    KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=6)),
)
def test_keys_are_equal_exactly_for_bisimilar_states(first, second):
    first, second = first.minimize(), second.minimize()
    assert (canonical_key(first) == canonical_key(second)) == bisimilar(first, second)


@settings(max_examples=100, deadline=None)
@given(KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=8)))
def test_canonical_classes_are_the_bisimulation_classes(model):
    labels, _ = canonical_classes(model)
    assert same_partition(labels, reference_classes(model))


def test_chain_needs_one_round_per_world_and_splits_all():
    """A path 0 -> 1 -> ... -> n-1 with p only at the end: every world is distinguished
    by its distance to p (n rounds of splitting, each of one world)."""
    n = 500
    initial = np.zeros(n, dtype=np.int64)
    initial[-1] = 1
    blocks = coarsest_partition(initial, np.arange(n - 1), np.arange(1, n), np.zeros(n - 1))
    assert len(set(blocks.tolist())) == n


def test_cycle_with_one_valuation_collapses_to_one_world():
    n = 1000
    m = KripkeModel.from_observables(["p"], {"a": ["p"]}, designated=["p"])
    big = KripkeModel(
        list(range(n)),
        {w: {"p"} for w in range(n)},
        {"a": [(w, (w + 1) % n) for w in range(n)]},
        [0],
    )
    assert big.minimize().n_worlds == 1
    assert bisimilar(big, m.announce("p"))  # one p-world that sees itself


@pytest.mark.parametrize("compared", [1 << 20, 2])
def test_refinement_is_exact_under_forced_hash_collisions(monkeypatch, compared):
    """With a hash that maps everything to one value, groups are found by the exact check
    (comparing the records in one piece, or a few nodes' records at a time)."""
    from epistemica.del_.explicit import _refinement

    monkeypatch.setattr(_refinement, "mix64", lambda values: np.zeros(len(values), np.uint64))
    monkeypatch.setattr(_refinement, "_COMPARED", compared)
    rng = np.random.default_rng(3)
    for _ in range(20):
        n = int(rng.integers(2, 30))
        m = int(rng.integers(0, 3 * n))
        sources, targets = rng.integers(0, n, m), rng.integers(0, n, m)
        labels = rng.integers(0, 2, m)
        initial = rng.integers(0, 2, n)
        initial = np.unique(initial, return_inverse=True)[1]
        found = coarsest_partition(initial, sources, targets, labels)
        expected = _naive_lts(initial, sources, targets, labels)
        assert same_partition(found.tolist(), expected)


def _naive_lts(initial, sources, targets, labels) -> list:
    label = list(initial.tolist())
    edges = list(zip(sources.tolist(), labels.tolist(), targets.tolist(), strict=True))
    while True:
        sig = [
            (label[w], frozenset((lab, label[v]) for s, lab, v in edges if s == w))
            for w in range(len(label))
        ]
        names: dict = {}
        refined = [names.setdefault(s, len(names)) for s in sig]
        if len(set(refined)) == len(set(label)):
            return refined
        label = refined


def test_every_pair_of_small_lts_agrees_with_the_naive_refinement():
    rng = np.random.default_rng(11)
    for n, m in itertools.product(range(1, 9), range(0, 14, 3)):
        sources, targets = rng.integers(0, n, m), rng.integers(0, n, m)
        labels = rng.integers(0, 3, m)
        initial = np.unique(rng.integers(0, 3, n), return_inverse=True)[1]
        found = coarsest_partition(initial, sources, targets, labels)
        assert same_partition(found.tolist(), _naive_lts(initial, sources, targets, labels))


def test_sparse_edges_with_computed_or_given_loneliness_agree_with_the_naive_refinement():
    """Few edges among many nodes (loneliness found by a sort, not a count per node and
    label), and the same graphs with each edge's loneliness given by the caller."""
    rng = np.random.default_rng(5)
    for _ in range(30):
        n, m = int(rng.integers(40, 120)), int(rng.integers(1, 12))
        sources, targets = rng.integers(0, n, m), rng.integers(0, n, m)
        labels = rng.integers(0, 3, m)
        initial = np.unique(rng.integers(0, 3, n), return_inverse=True)[1]
        expected = _naive_lts(initial, sources, targets, labels)
        pairs = list(zip(sources.tolist(), labels.tolist(), strict=True))
        alone = np.array([pairs.count(pair) == 1 for pair in pairs])
        for hint in (None, alone):
            found = coarsest_partition(initial, sources, targets, labels, hint)
            assert same_partition(found.tolist(), expected)


def muddy_with_hidden_atoms(n: int, hidden: int) -> KripkeModel:
    """Muddy children's 2^n worlds and partitions, only the last n - hidden atoms kept."""
    atoms = [f"m{i}" for i in range(1, n + 1)]
    observes = {f"c{i}": atoms[: i - 1] + atoms[i:] for i in range(1, n + 1)}
    full = KripkeModel.from_observables(atoms, observes, designated=atoms)
    return KripkeModel.from_arrays(
        None,
        full.atoms[hidden:],
        np.ascontiguousarray(full.valuation[:, hidden:]),
        full.agents,
        dict(full.belief_relations),
        dict(full.knowledge_relations),
        full.designated_positions,
    )


def test_muddy_children_with_hidden_atoms_merge_exactly_by_the_visible_ones():
    """Flipping a hidden atom maps the model onto itself and keeps the valuation, so
    worlds merge exactly when they agree on the visible atoms (the partitions' labels
    leave half their range unused: empty classes)."""
    model = muddy_with_hidden_atoms(7, 3)
    visible = [tuple(row) for row in model.valuation.tolist()]
    classes = bisimulation_classes(model)
    assert same_partition(classes.tolist(), visible)
    assert same_partition(classes.tolist(), reference_classes(model))
    assert model.minimize().n_worlds == 2 ** (7 - 3)


def test_distinct_valuations_are_distinct_classes_without_refining():
    model = muddy_with_hidden_atoms(6, 0)
    assert same_partition(bisimulation_classes(model).tolist(), list(range(64)))
    assert model.minimize().n_worlds == 64


def reference_key(model) -> tuple:
    """The canonical key as first written (tuples, no contraction first): names are ranks
    of (label, sorted reached labels per agent and relation), refined to a fixed point."""
    worlds = list(model.worlds)
    succ = [
        {w: model.successors(a, w, relation=kind) for w in worlds}
        for a in sorted(model.agents)
        for kind in ("belief", "knowledge")
    ]
    label = {w: tuple(sorted(model.valuation_of(w))) for w in worlds}
    while True:
        described = {
            w: (label[w], *(tuple(sorted({label[v] for v in s[w]})) for s in succ)) for w in worlds
        }
        ranks = {d: i for i, d in enumerate(sorted(set(described.values())))}
        refined = {w: ranks[described[w]] for w in worlds}
        if len(ranks) == len(set(label.values())):
            break
        label = refined
    table = tuple(sorted({(tuple(sorted(model.valuation_of(w))), described[w]) for w in worlds}))
    return table, tuple(sorted({described[w] for w in model.designated}))


@settings(max_examples=150, deadline=None)
@given(
    KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=6)),
    KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=6)),
)
def test_keys_agree_with_the_first_implementation(first, second):
    first, second = generated_submodel(first), generated_submodel(second)
    same = canonical_key(first) == canonical_key(second)
    assert same == (reference_key(first) == reference_key(second))


@settings(max_examples=150, deadline=None)
@given(
    KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=7)),
    KINDS.flatmap(lambda kind: models(kind=kind, max_worlds=7)),
    st.integers(0, 2**32 - 1),
)
def test_every_refinement_path_gives_exact_keys(monkeypatch_free, second, seed):
    """The hashed path (many classes) and the contract-first path, forced on small
    states: keys stay invariant under permutation and equal exactly for bisimilar states."""
    from epistemica.del_.explicit import canonical

    first = generated_submodel(monkeypatch_free)
    second = generated_submodel(second)
    other = permuted(first, seed)
    saved = canonical._MASK_BITS, canonical.CONTRACT_ABOVE
    try:
        for mask_bits, contract_above in ((0, 10**9), (62, 0), (0, 0)):
            canonical._MASK_BITS, canonical.CONTRACT_ABOVE = mask_bits, contract_above
            key = canonical_key(first)
            assert key == canonical_key(other)
            assert (key == canonical_key(second)) == bisimilar(first, second)
            labels, _ = canonical_classes(first)
            assert same_partition(labels, reference_classes(first))
    finally:
        canonical._MASK_BITS, canonical.CONTRACT_ABOVE = saved


def test_a_successor_set_shared_by_every_class_is_keyed_once(monkeypatch):
    """Agent a considers all 256 worlds possible, b tells them apart (distinct valuations):
    every class has a's one successor set, which the key lists once, not once per class
    (256 x 256 labels; plank's Tiger needed 3 GiB so). The key is still canonical."""
    from epistemica.del_.explicit import canonical

    monkeypatch.setattr(canonical, "_MASK_BITS", 0)  # the hashed path, for many classes
    atoms = [f"p{i}" for i in range(8)]
    model = KripkeModel.from_observables(atoms, {"a": [], "b": atoms}, designated=atoms)
    key = canonical_key(model)
    size = sum(len(part) for part in key[1])
    assert size < 128 * model.n_worlds  # the old listing of a alone: 2 * 8 * 256 * 256 bytes
    assert key == canonical_key(permuted(model, 4))
    assert key != canonical_key(model.repoint([0]))


def test_contraction_and_search_respect_the_memory_budget():
    """Contraction needs about BYTES_PER_EDGE per edge of its graph; refused above the
    budget with a MemoryBudgetError naming it, done below."""
    from epistemica.del_.budget import MemoryBudgetError, budget_scope
    from epistemica.del_.explicit.bisimulation import BYTES_PER_EDGE

    model = muddy_with_hidden_atoms(8, 4)
    needed = BYTES_PER_EDGE * 8 * (256 + 256)  # per agent: world -> pair, pair -> worlds
    with budget_scope(needed - 1), pytest.raises(MemoryBudgetError, match="contracting"):
        bisimulation_classes(model)
    with budget_scope(needed):
        assert len(set(bisimulation_classes(model).tolist())) == 16
