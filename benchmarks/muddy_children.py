"""Muddy children end to end: the figures behind docs/performance.md.

All n children are muddy. One run builds the model from observables, announces the
father's "at least one of you is muddy", then announces "nobody knows whether they are
muddy" until the muddy children know (n - 1 rounds, the published answer, asserted).

Two evaluation paths are timed: the bitset path that models from observables use, and
the general path (label partitions over compact worlds) that every other model uses,
forced by restricting the model to all its worlds.

Usage: python benchmarks/muddy_children.py [--max-n 20] [--repeat 5] [--general-max-n 20]
"""

from __future__ import annotations

import argparse
import statistics
import time
import tracemalloc

import numpy as np

from epistemica.del_ import KripkeModel


def solve(n: int, general: bool = False) -> int:
    """Run the puzzle; return the number of "nobody knows" rounds."""
    atoms = [f"m{i}" for i in range(1, n + 1)]
    observes = {f"c{i}": atoms[: i - 1] + atoms[i:] for i in range(1, n + 1)}
    model = KripkeModel.from_observables(atoms, observes, designated=atoms)
    if general:
        model = model.restrict(np.ones(model.n_worlds, dtype=bool))
    model = model.announce(" | ".join(atoms))
    nobody_knows = " & ".join(f"~Kw[c{i}] m{i}" for i in range(1, n + 1))
    they_know = " & ".join(f"Kw[c{i}] m{i}" for i in range(1, n + 1))
    rounds = 0
    while not model.holds(they_know):
        model = model.announce(nobody_knows)
        rounds += 1
    if rounds != n - 1:
        raise AssertionError(f"{n} muddy children should know after {n - 1} rounds, not {rounds}")
    return rounds


def measure(n: int, repeat: int, general: bool) -> tuple[float, float]:
    """Median seconds over ``repeat`` runs, and peak traced memory (MiB) of one run."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        solve(n, general)
        times.append(time.perf_counter() - start)
    tracemalloc.start()
    solve(n, general)
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return statistics.median(times), peak


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--min-n", type=int, default=4)
    parser.add_argument("--max-n", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--general-max-n", type=int, default=20)
    args = parser.parse_args()
    print("| children | worlds | bitset: median s | peak MiB | general: median s | peak MiB |")
    print("|---:|---:|---:|---:|---:|---:|")
    for n in range(args.min_n, args.max_n + 1):
        fast, fast_peak = measure(n, args.repeat, general=False)
        if n <= args.general_max_n:
            slow, slow_peak = measure(n, max(1, args.repeat if n <= 16 else 1), general=True)
            general_cells = f"{slow:.4f} | {slow_peak:.1f}"
        else:
            general_cells = "– | –"
        print(f"| {n} | {2**n:,} | {fast:.4f} | {fast_peak:.1f} | {general_cells} |", flush=True)


if __name__ == "__main__":
    main()
