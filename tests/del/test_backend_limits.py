"""Deep, wide and shared input on both backends: the same formulas, the same answers.

The explicit checker and the symbolic evaluator both walk formulas on an explicit stack;
these tests give each the formulas docs/language.md promises (10,000 deep, 100,000 wide)
and hypothesis' deep prefixes and wide chains, and compare the answers with each other and
with values worked out by hand. They also check the symbolic backend's variable
bookkeeping: counts of structures that share the one BDD manager.
"""

from __future__ import annotations

import itertools
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import (
    And,
    Announce,
    AnnounceDiamond,
    Atom,
    Common,
    Iff,
    Implies,
    Know,
    KnowledgeStructure,
    KnowWhether,
    KripkeModel,
    Not,
    Or,
)

from epistemic_strategies import explicit_copy

DEEP = 10_000
WIDE = 100_000
P, Q = Atom("p"), Atom("q")
OBSERVES = {"a": ["q"], "b": ["p"]}


def _backends(designated=("p",)):
    """The same two-atom S5 model: on bitsets, as explicit worlds, and as a BDD structure."""
    cube = KripkeModel.from_observables(["p", "q"], OBSERVES, designated=list(designated))
    plain = explicit_copy(cube)
    symbolic = KnowledgeStructure.from_observables(["p", "q"], OBSERVES, designated=designated)
    return {"bitsets": cube, "explicit": plain, "symbolic": symbolic}


BACKENDS = ["bitsets", "explicit", "symbolic"]


def _count(model, f) -> int:
    """Worlds where ``f`` holds, on either backend."""
    if isinstance(model, KnowledgeStructure):
        return model.count(f)
    return len(model.truth_set(f))


@pytest.mark.parametrize("backend", BACKENDS)
def test_ten_thousand_negations_and_knowledge(backend):
    model = _backends()[backend]
    negations, same, alternating = P, Q, Q
    for i in range(DEEP):  # an even number of negations is the atom itself
        negations = Not(negations)
        same = Know("a", same)  # S5: K[a] K[a] ... q is K[a] q (a sees q)
        alternating = Know("a" if i % 2 else "b", alternating)  # q fails somewhere
    assert model.holds(negations) and _count(model, negations) == 2
    assert _count(model, same) == 2  # the two q-worlds
    assert _count(model, alternating) == 0


@pytest.mark.parametrize("left_deep", [True, False])
def test_hundred_thousand_term_chains(left_deep):
    """The explicit backend's run of this test is in test_checker_limits.py."""
    model = _backends()["symbolic"]
    terms = [P, Q, Not(Q)] * (WIDE // 3)
    conj = disj = impl = terms[0]
    for t in terms[1:]:
        conj = And(conj, t) if left_deep else And(t, conj)
        disj = Or(disj, t) if left_deep else Or(t, disj)
        impl = Implies(t, impl)
    assert _count(model, conj) == 0  # q & ~q
    assert _count(model, disj) == 4  # q | ~q
    assert _count(model, impl) == 4  # the premises q and ~q never hold together


@pytest.mark.parametrize("backend", BACKENDS)
def test_deep_announcements(backend):
    """[!p][!p]...[!p] K[b] p: after announcing p, b knows it, however often it is said."""
    model = _backends()[backend]
    f = Know("a", P)
    for _ in range(2_000):
        f = Announce(P, f)
    assert _count(model, f) == 4


def test_deep_law_on_the_symbolic_backend():
    law = P
    for _ in range(DEEP):
        law = Not(Not(law))
    s = KnowledgeStructure.from_observables(["p", "q"], OBSERVES, law=law)
    assert s.n_worlds == 2 and s.holds("p")


def test_shared_subformulas_are_computed_once():
    """f_{k+1} = f_k & f_k: 2^60 leaves, 61 distinct nodes; both backends answer at once."""
    f = P
    for _ in range(60):
        f = And(f, f)
    for backend in BACKENDS:
        assert _count(_backends()[backend], f) == 2


# -- hypothesis: random deep prefixes and wide chains, both backends ----------------------

UNARY = {
    "~": Not,
    "K[a]": lambda f: Know("a", f),
    "K[b]": lambda f: Know("b", f),
    "Kw[a]": lambda f: KnowWhether("a", f),
    "C[a,b]": lambda f: Common(("a", "b"), f),
    "[!q]": lambda f: Announce(Q, f),
    "<!~p>": lambda f: AnnounceDiamond(Not(P), f),
}
BINARY = {"&": And, "|": Or, "->": Implies, "<->": Iff}
DESIGNATED = st.sampled_from([(), ("p",), ("q",), ("p", "q")])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.sampled_from(sorted(UNARY)), max_size=3000), DESIGNATED)
def test_random_deep_prefixes_agree(ops, designated):
    f = P
    for op in reversed(ops):
        f = UNARY[op](f)
    models = _backends(designated)
    counts = {name: _count(m, f) for name, m in models.items()}
    holds = {name: m.holds(f) for name, m in models.items()}
    assert len(set(counts.values())) == 1, counts
    assert len(set(holds.values())) == 1, holds


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.tuples(st.sampled_from(sorted(BINARY)), st.sampled_from(["p", "q", "~p", "~q"])),
        max_size=3000,
    ),
    st.booleans(),
    DESIGNATED,
)
def test_random_wide_chains_agree_with_a_direct_count(items, right, designated):
    f = P
    values = {(vp, vq): vp for vp, vq in itertools.product((False, True), repeat=2)}
    for symbol, name in items:
        term = Not(Atom(name[1])) if name.startswith("~") else Atom(name)
        f = BINARY[symbol](term, f) if right else BINARY[symbol](f, term)
        for vp, vq in values:
            t = {"p": vp, "q": vq, "~p": not vp, "~q": not vq}[name]
            old = values[vp, vq]
            a, b = (t, old) if right else (old, t)
            values[vp, vq] = {"&": a and b, "|": a or b, "->": (not a) or b, "<->": a == b}[symbol]
    expected = sum(values.values())  # the four valuations are the four worlds
    for model in _backends(designated).values():
        assert _count(model, f) == expected


# -- the symbolic backend's variable bookkeeping --------------------------------------------


def test_a_fresh_manager_counts_a_structure_whose_variables_it_never_made():
    """The structure with two unobserved atoms and no law: 4 states, on a new manager."""
    code = (
        "from epistemica.del_ import KnowledgeStructure\n"
        "s = KnowledgeStructure.from_observables(['p', 'q'], {'a': []})\n"
        "print(s.n_worlds, s.count('p'), s.count_designated())\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["4", "2", "4"]


@st.composite
def _structures(draw):
    n = draw(st.integers(1, 7))
    atoms = [f"x{i}" for i in range(n)]
    law = draw(st.sampled_from([None, "x0 | ~x0", "x0", f"x0 -> x{n - 1}", f"~(x0 & x{n - 1})"]))
    observes = {"a": draw(st.lists(st.sampled_from(atoms), unique=True))}
    return atoms, observes, law


@settings(max_examples=60, deadline=None)
@given(st.lists(_structures(), min_size=1, max_size=6), st.randoms(use_true_random=False))
def test_counts_of_structures_sharing_one_manager(specs, rng):
    """Structures of 1 to 7 atoms built in any order on the shared manager count their
    states as enumerating the valuations does (the explicit backend)."""
    built = []
    for atoms, observes, law in specs:
        s = KnowledgeStructure.from_observables(atoms, observes, law)
        built.append((s, KripkeModel.from_observables(atoms, observes, law)))
    rng.shuffle(built)
    for s, m in built:
        assert s.n_worlds == m.n_worlds
        assert s.count("x0") == len(m.truth_set("x0"))
        assert s.count("K[a] x0") == len(m.truth_set("K[a] x0"))
