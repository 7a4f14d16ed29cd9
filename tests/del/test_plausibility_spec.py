"""Plausibility orders and soft upgrades in spec files: the declarations, the backends they
build, and the located errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from epistemica.cli import main
from epistemica.del_.errors import SpecError
from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.spec import load_spec, parse_spec
from epistemica.del_.symbolic.plausibility import PlausibilityStructure

MARY = Path(__file__).resolve().parents[2] / "specs" / "belief" / "mary_and_john.epi"

COIN = """
agents alice, bob
atoms h
observes bob: h
actual {h}
plausibility alice: ~h          # tails first; the h-world comes after
upgrade hint: radical h
"""


@pytest.mark.parametrize("backend", ["explicit", "symbolic"])
def test_mary_and_john_spec_on_both_backends(backend):
    spec = load_spec(MARY, backend)
    kind = PlausibilityModel if backend == "explicit" else PlausibilityStructure
    assert isinstance(spec.plausibility, kind)
    assert [c.name for c in spec.checks if spec.holds(c.formula) != c.expected] == []
    assert spec.upgrades["hint_of_cheating"][0] == "conservative"


def test_named_upgrade_is_the_upgrade_operator():
    spec = parse_spec(COIN)
    for text in ["B[alice] h", "K[alice] h", "B[alice] K[bob] h", "B[alice | ~h] h"]:
        assert spec.holds(f"[hint] {text}") == spec.holds(f"[^^h] {text}"), text
    # By hand: alice's order is ~h < h; after ^^h it is h < ~h.
    assert spec.holds("B[alice] ~h & [hint] B[alice] h & ~[hint] K[alice] h")
    # Agents without a plausibility line find every world equally plausible: B is K.
    assert spec.holds("B[bob] h & Sb[bob] h")


def test_levels_with_a_range_of_agents_and_a_law():
    spec = parse_spec(
        """
        agents a1..a2
        atoms p, q
        law p | q
        actual {p}
        plausibility a1..a2: p & q, q
        """
    )
    # Worlds: {p} (rank 2), {q} (1), {p, q} (0); no one observes anything.
    assert spec.holds("B[a1] (p & q) & B[a2 | ~q] p & B[a1 | ~(p & q)] q")
    assert spec.holds("~Sb[a1] q")  # at {p} (rank 2) every world counts: {p} has ~q


@pytest.mark.parametrize(
    "text, message, where",
    [
        ("agents a\natoms p\nupgrade u: radical p\n", "needs a plausibility order", "3:1"),
        (
            "agents a\natoms p\nworld w {p}\nrelation a: w -> w\ndesignated w\nplausibility a: p\n",
            "needs the model by observation",
            "6:1",
        ),
        (
            "agents a\natoms p\nplausibility a: p\nplausibility a: ~p\n",
            "second plausibility",
            "4:14",
        ),
        ("agents a\natoms p\nplausibility a: K[a] p\n", "must be propositional", "3:17"),
        ("agents a\natoms p\nplausibility b: p\n", "unknown agent 'b'", "3:14"),
        ("agents a\natoms p\nplausibility a: q\n", "unknown atom 'q'", "3:17"),
        (
            "agents a\natoms p\naction u: public p\nplausibility a: p\nupgrade u: radical p\n",
            "declared twice",
            "5:9",
        ),
        (
            "agents a\natoms p\naction tell: public p\nplausibility a: p\n"
            'check "x": [tell] K[a] p\n',
            "uses the action 'tell'",
            "5:1",
        ),
        (
            'agents a\natoms p\nplausibility a: p\ncheck "x": p\ncheck "y": C[a] p\n',
            "uses C",
            "5:1",
        ),
    ],
)
def test_located_errors(text, message, where):
    with pytest.raises(SpecError, match=message) as info:
        parse_spec(text, "t.epi")
    assert f"t.epi:{where}:" in str(info.value)


def test_cli_checks_and_single_formulas(capsys):
    assert main(["check", str(MARY)]) == 0
    assert "12 passed, 0 failed" in capsys.readouterr().out
    # --formula is evaluated in the plausibility model too (B is plausibility belief)
    assert main(["check", str(MARY), "-f", "B[mary] ~c"]) == 0
    capsys.readouterr()
    # a question exits 0 and prints its answer; with --expect it is a claim
    assert main(["check", str(MARY), "-f", "[colleague_says_late] [^^c] B[mary] ~c"]) == 0
    assert "false" in capsys.readouterr().out
    after = "[colleague_says_late] [^^c] B[mary] ~c"
    assert main(["check", str(MARY), "-f", after, "--expect", "true"]) == 1
    capsys.readouterr()
    assert main(["check", str(MARY), "-f", "B[mary | ] c"]) == 2
    assert "expected a formula" in capsys.readouterr().err
