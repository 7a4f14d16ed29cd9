"""Benchmark: the explicit and symbolic plausibility backends on random models, and the
symbolic one on models too large to list.

Part 1 (agreement): ``--models`` random plausibility models (seeded numpy Generator): 2 to
4 atoms, a random nonempty set of lawful valuations, 2 agents each observing a random
subset of the atoms and ranking every world 0..3 at random; for each, ``--formulas``
random formulas of depth up to 4 over every operator the plausibility language has
(``K``, ``Kw``, ``B``, ``B[a | c]``, ``Sb``, ``E``, ``EB``, ``[!c]``, ``<!c>``, ``[^^c]``,
``[^c]``). Every formula is evaluated at every world by both backends; the count of
(model, formula, world) triples on which they differ is printed (the target is 0).

Part 2 (scale): n coins, an agent that observes none of them and finds "all tails" most
plausible, one that observes all; the median time of a conditional-belief formula after a
radical and a conservative upgrade on the symbolic backend, for growing n (2^n worlds).

Usage: ``python benchmarks/plausibility_agreement.py [--models 1000] [--formulas 5]
[--seed 0]``; prints the counts and a markdown table.
"""

from __future__ import annotations

import argparse
import itertools
import statistics
import time

import numpy as np

from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.language.formula import And, Atom, Bottom, Formula, Implies, Not, Or, Top
from epistemica.del_.language.modalities import (
    Announce,
    AnnounceDiamond,
    Believe,
    ConditionalBelief,
    ConservativeUpgrade,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
    RadicalUpgrade,
    SafeBelief,
)
from epistemica.del_.symbolic.plausibility import PlausibilityStructure

AGENTS = ("a", "b")
UNARY = (Not, Know, KnowWhether, Believe, SafeBelief, Everybody, EverybodyBelieves)
BINARY = (And, Or, Implies, ConditionalBelief, Announce, AnnounceDiamond)
BINARY += (RadicalUpgrade, ConservativeUpgrade)


def random_model(rng: np.random.Generator) -> PlausibilityModel:
    k = int(rng.integers(2, 5))
    atoms = [f"p{j}" for j in range(k)]
    table = np.array(list(itertools.product((False, True), repeat=k)), dtype=bool)
    keep = rng.random(len(table)) < 0.7
    keep[rng.integers(len(table))] = True
    valuation = table[keep]
    n = len(valuation)
    observes, cells, ranks = {}, {}, {}
    for agent in AGENTS:
        seen = [j for j in range(k) if rng.random() < 0.4]
        observes[agent] = [atoms[j] for j in seen]
        cells[agent] = valuation[:, seen] @ (1 << np.arange(len(seen), dtype=np.int64))
        ranks[agent] = rng.integers(0, 4, n)
    designated = rng.random(n) < 0.5
    return PlausibilityModel(atoms, valuation, cells, ranks, designated, observes)


def random_formula(rng: np.random.Generator, atoms: list[str], depth: int) -> Formula:
    if depth == 0 or rng.random() < 0.2:
        choice = int(rng.integers(len(atoms) + 2))
        return (
            Atom(atoms[choice]) if choice < len(atoms) else (Top(), Bottom())[choice - len(atoms)]
        )
    agent = str(rng.choice(AGENTS))
    if rng.random() < 0.5:
        kind = UNARY[int(rng.integers(len(UNARY)))]
        inner = random_formula(rng, atoms, depth - 1)
        if kind is Not:
            return Not(inner)
        if kind in (Everybody, EverybodyBelieves):
            return kind(AGENTS[: int(rng.integers(1, 3))], inner)
        return kind(agent, inner)
    kind = BINARY[int(rng.integers(len(BINARY)))]
    left, right = (random_formula(rng, atoms, depth - 1) for _ in range(2))
    if kind is ConditionalBelief:
        return ConditionalBelief(agent, left, right)
    return kind(left, right)


def agreement(n_models: int, n_formulas: int, seed: int) -> tuple[int, int, int]:
    rng = np.random.default_rng(seed)
    disagreements = checked = 0
    for _ in range(n_models):
        model = random_model(rng)
        structure = PlausibilityStructure.from_explicit(model)
        for _ in range(n_formulas):
            f = random_formula(rng, list(model.atoms), 4)
            explicit = model.truth(f)
            for w in range(model.n_worlds):
                checked += 1
                disagreements += structure.holds_at(f, model.valuation[w]) != bool(explicit[w])
    return n_models, checked, disagreements


def scale(sizes: list[int], repeats: int) -> list[tuple[int, float]]:
    rows = []
    PlausibilityStructure.from_levels(["h"], {"alice": ["h"]}).holds("B[alice] h")  # warm-up
    for n in sizes:
        coins = [f"h{i}" for i in range(n)]
        tails = " & ".join(f"~{c}" for c in coins)
        # By hand: after ^^(h0 & ~h1) alice's levels are h0~h1 < all tails < the rest;
        # ^h2 lifts h0~h1h2 to the top, so her best h3-worlds satisfy h0 & h2. The actual
        # world (h0..h3 true) is in "the rest": h0~h1~h2 is more plausible, so h2 is not
        # safely believed; bob observes every coin.
        formula = "[^^h0 & ~h1] [^h2] (B[alice | h3] (h0 & h2) & ~Sb[alice] h2 & K[bob] h0)"
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            s = PlausibilityStructure.from_levels(
                coins, {"alice": [tails], "bob": []}, {"bob": coins}, designated=coins[:4]
            )
            assert s.holds(formula)
            times.append(time.perf_counter() - start)
        rows.append((n, statistics.median(times)))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", type=int, default=1000)
    parser.add_argument("--formulas", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    start = time.perf_counter()
    models, checked, disagreements = agreement(args.models, args.formulas, args.seed)
    took = time.perf_counter() - start
    print(
        f"{models} random models, {models * args.formulas} formulas, {checked} (formula, "
        f"world) evaluations: {disagreements} disagreements ({took:.1f} s)"
    )
    print("\n| coins | worlds | median time (ms) |\n|---|---|---|")
    for n, t in scale([10, 50, 100, 200], args.repeats):
        print(f"| {n} | 2^{n} | {1000 * t:.1f} |")


if __name__ == "__main__":
    main()
