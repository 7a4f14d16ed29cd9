"""The shipped puzzle specs: their claims, and the published answers they encode.

The claims inside the files were written from the puzzles' published solutions; these
tests evaluate them through the Python API and, independently of the files' wording,
check the published answers again with formulas built here.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from epistemica.del_ import load_spec

PUZZLES = Path(__file__).resolve().parents[2] / "specs" / "puzzles"
FILES = sorted(PUZZLES.glob("*.epi"))


def test_the_puzzles_are_shipped():
    names = {p.name for p in FILES}
    assert {
        "muddy_children.epi",
        "muddy_children_4.epi",
        "sally_anne.epi",
        "coin_toss.epi",
        "dining_cryptographers_100.epi",
        "drinking_logicians_400.epi",
        "sum_and_product.epi",
    } <= names


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_every_claim_meets_its_expectation(path):
    spec = load_spec(path)
    assert spec.checks, "a puzzle spec should state its published answers as claims"
    failed = [c.name for c in spec.checks if spec.holds(c.formula) != c.expected]
    assert failed == []


def _nobody_knows(n: int) -> str:
    return " & ".join(f"~Kw[c{i}] m{i}" for i in range(1, n + 1))


def _everybody_knows(n: int) -> str:
    return " & ".join(f"K[c{i}] m{i}" for i in range(1, n + 1))


@pytest.mark.parametrize(("name", "n"), [("muddy_children", 3), ("muddy_children_4", 4)])
def test_muddy_children_know_after_n_minus_one_rounds(name, n):
    """All n muddy: nobody knows after the father and r < n-1 rounds; all know after n-1."""
    spec = load_spec(PUZZLES / f"{name}.epi")
    for rounds in range(n):
        prefix = "[father]" + "[nobody_knows]" * rounds
        if rounds < n - 1:
            assert spec.holds(f"{prefix} ({_nobody_knows(n)})"), rounds
            assert not spec.holds(f"{prefix} K[c1] m1"), rounds
        else:
            assert spec.holds(f"{prefix} ({_everybody_knows(n)})"), rounds


@pytest.mark.parametrize(("name", "n"), [("muddy_children", 3), ("muddy_children_4", 4)])
def test_muddy_children_surviving_worlds(name, n):
    """After the father and r rounds, exactly the worlds with >= r+1 muddy children remain."""
    spec = load_spec(PUZZLES / f"{name}.epi")
    model = spec.model
    for rounds in range(n):
        for combo in itertools.product([False, True], repeat=n):
            state = " & ".join(f"{'' if v else '~'}m{i + 1}" for i, v in enumerate(combo))
            prefix = "[father]" + "[nobody_knows]" * rounds
            # ~[a1][a2]... false holds exactly where the announcements can all be made.
            alive = f"~{prefix} false"
            world = next(w for w in model.worlds if _matches(model.valuation_of(w), combo))
            survives = world in model.truth_set(spec.formula(alive), spec.actions)
            assert survives == (sum(combo) >= rounds + 1), (rounds, state)


def _matches(true_atoms, combo) -> bool:
    return all((f"m{i + 1}" in true_atoms) == v for i, v in enumerate(combo))


def test_sally_anne_false_belief():
    spec = load_spec(PUZZLES / "sally_anne.epi")
    story = "[sally_leaves][anne_moves][sally_returns]"
    assert spec.holds(f"{story} (box & ~basket)")
    assert spec.holds(f"{story} B[sally] basket")  # the false belief
    assert spec.holds(f"{story} ~K[sally] basket & ~K[sally] box")  # no knowledge either way
    assert spec.holds(f"{story} K[anne] B[sally] basket")
    assert spec.holds(f"{story} K[anne] box")


def test_coin_toss_shown_to_b():
    spec = load_spec(PUZZLES / "coin_toss.epi")
    shown = "[toss][show_b]"
    assert spec.holds(f"{shown} (Kw[b] heads & ~Kw[a] heads & K[a] Kw[b] heads)")
    assert spec.holds("[toss] ~Kw[b] heads")  # before looking, b does not know


def test_sum_and_product_has_the_unique_solution_four_and_thirteen():
    """Freudenthal's puzzle: after 'S: I knew you didn't know', 'P: now I know' and 'S: now
    I know too', exactly one pair is left, x = 4 and y = 13 (of the 2,352 pairs)."""
    spec = load_spec(PUZZLES / "sum_and_product.epi")
    model = spec.model
    assert model.n_worlds == 2352  # 2 <= x < y, x + y <= 100
    for name in ("s_knew_it", "p_knows", "s_knows"):
        model = model.update(spec.actions[name])
    assert model.n_worlds == 1
    four, thirteen = "~x1 & ~x2 & ~x3 & x4 & ~x5 & ~x6", "~y1 & ~y2 & ~y3 & y4 & y5 & ~y6 & y7"
    assert model.holds(f"{four} & {thirteen}")
