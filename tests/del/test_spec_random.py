"""Random specs written as text compile to the model their declarations describe.

Each example draws agents, atoms, what each agent observes, a law, an actual world and
formulas, prints them as a spec file (formulas via ``str()``), compiles it, and compares
the truth of every formula at every world with a brute-force evaluation built straight
from the declarations: the worlds are the valuations satisfying the law, and an agent
cannot tell two of them apart when they agree on the atoms it observes.
"""

from __future__ import annotations

import functools
import itertools

from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import And, Atom, Iff, Implies, Not, Or, SpecError, Top, parse_spec

from epistemic_strategies import _truth, formulas

AGENTS = ("a", "b", "c")
ATOMS = ("p", "q", "at(r1, g1)")


@functools.cache
def _formulas(atoms: tuple[str, ...], agents: tuple[str, ...]):
    # Built once per signature: building recursive strategies dominates the run time.
    return formulas(atoms=atoms, agents=agents, max_leaves=8)


@functools.cache
def _laws(atoms: tuple[str, ...]):
    leaves = st.one_of(st.sampled_from([Atom(a) for a in atoms]), st.just(Top()))
    return st.recursive(
        leaves,
        lambda sub: st.one_of(
            sub.map(Not), st.builds(And, sub, sub), st.builds(Or, sub, sub),
            st.builds(Implies, sub, sub), st.builds(Iff, sub, sub),
        ),
        max_leaves=5,
    )  # fmt: skip


@st.composite
def specs(draw):
    agents = AGENTS[: draw(st.integers(1, len(AGENTS)))]
    atoms = ATOMS[: draw(st.integers(1, len(ATOMS)))]
    observes = {a: draw(st.lists(st.sampled_from(atoms), unique=True)) for a in agents}
    law = draw(st.none() | _laws(atoms))
    actual = draw(st.none() | st.lists(st.sampled_from(atoms), unique=True))
    checks = draw(st.lists(_formulas(atoms, agents), max_size=3))
    return agents, atoms, observes, law, actual, checks


def render(agents, atoms, observes, law, actual, checks) -> str:
    lines = [f"agents {', '.join(agents)}  # random", f"atoms {', '.join(atoms)}"]
    lines += [f"observes {a}: {', '.join(seen)}" for a, seen in observes.items() if seen]
    if law is not None:
        lines.append(f"law {law}")
    if actual is not None:
        lines.append(f"actual {{{', '.join(actual)}}}")
    lines += [f'check "c{i}": {f}' for i, f in enumerate(checks)]
    return "\n".join(lines) + "\n"


def brute_force(agents, atoms, observes, law):
    """Worlds (frozensets of true atoms) and each agent's indistinguishability pairs."""
    worlds = []
    for bits in itertools.product([False, True], repeat=len(atoms)):
        world = frozenset(a for a, bit in zip(atoms, bits, strict=True) if bit)
        if law is None or _truth(law, frozenset([world]), {world: world}, {}, {}):
            worlds.append(world)
    pairs = {
        a: {(w, v) for w in worlds for v in worlds if w & set(seen) == v & set(seen)}
        for a, seen in observes.items()
    }
    return worlds, pairs


@settings(max_examples=60)
@given(specs())
def test_random_specs_match_brute_force(drawn):
    agents, atoms, observes, law, actual, checks = drawn
    text = render(*drawn)
    worlds, pairs = brute_force(agents, atoms, observes, law)
    actual_world = None if actual is None else frozenset(actual)
    if not worlds or (actual_world is not None and actual_world not in worlds):
        try:
            parse_spec(text)
        except SpecError as err:
            assert "law" in err.message and err.line is not None
            return
        raise AssertionError("an unsatisfiable law or a law-breaking actual world was accepted")

    spec = parse_spec(text)
    model = spec.model
    assert spec.agents == agents and spec.atoms == atoms
    assert sorted(map(sorted, (model.valuation_of(w) for w in model.worlds))) == sorted(
        map(sorted, worlds)
    )
    designated = {model.valuation_of(w) for w in model.designated}
    assert designated == (set(worlds) if actual_world is None else {actual_world})
    for check, f in zip(spec.checks, checks, strict=True):
        assert str(check.formula) == str(f)  # the printed formula parses back in a spec
        expected = _truth(f, frozenset(worlds), {w: w for w in worlds}, pairs, pairs)
        got = {model.valuation_of(w) for w in model.truth_set(check.formula)}
        assert got == expected, (text, str(f))
        assert spec.holds(check.formula) == (designated <= expected)
