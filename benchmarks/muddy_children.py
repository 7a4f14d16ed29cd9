"""Muddy children end to end: the figures behind docs/performance.md.

All n children are muddy. One run builds the model from observables, announces the
father's "at least one of you is muddy", then announces "nobody knows whether they are
muddy" until the muddy children know (n - 1 rounds, the published answer, asserted).

Two evaluation paths are timed: the bitset path that models from observables use, and
the general path (label partitions over compact worlds) that every other model uses,
forced by restricting the model to all its worlds.

With ``--cli N [N ...]`` it measures instead the command line of issue 12 on the shipped
spec scaled to N children (3 muddy): ``epistemica check SPEC --formula "[father]
[nobody_knows][nobody_knows] (K[c1] m1 & K[c2] m2 & K[c3] m3)" --backend explicit``, in a
fresh interpreter per run (wall time including start-up, and its peak RSS), and the same
check in-process (load, ``holds`` and ``truth_mask``; peak RSS of that process).

Usage: python benchmarks/muddy_children.py [--max-n 20] [--repeat 5] [--general-max-n 20]
       python benchmarks/muddy_children.py --cli 16 20 22 24 [--repeat 3]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

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


CLI_FORMULA = "[father][nobody_knows][nobody_knows] (K[c1] m1 & K[c2] m2 & K[c3] m3)"

# Runs the CLI (or the in-process check) and prints its peak RSS in KiB on stderr.
_RUN_CLI = """
import resource, sys
from epistemica.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
print("RSS", resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)
"""
_RUN_INPROCESS = """
import resource, sys, time
from epistemica.del_ import load_spec
spec = load_spec(sys.argv[1])
start = time.perf_counter()
formula = spec.formula(sys.argv[2])
assert spec.model.holds(formula, spec.actions)
spec.model.truth_mask(formula, spec.actions)
print("TIME", time.perf_counter() - start, file=sys.stderr)
print("RSS", resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)
"""


def scaled_spec(n: int, folder: Path) -> Path:
    """specs/puzzles/muddy_children.epi for n children, the first three muddy."""
    atoms = [f"m{i}" for i in range(1, n + 1)]
    lines = [f"agents c1..c{n}", f"atoms m1..m{n}"]
    for i in range(1, n + 1):
        lines.append(f"observes c{i}: " + ", ".join(a for a in atoms if a != f"m{i}"))
    lines.append("actual {m1, m2, m3}")
    lines.append("action father: public " + " | ".join(atoms))
    nobody = " & ".join(f"~Kw[c{i}] m{i}" for i in range(1, n + 1))
    lines.append(f"action nobody_knows: public {nobody}")
    path = folder / f"muddy_children_{n}.epi"
    path.write_text("\n".join(lines) + "\n")
    return path


def _child(script: str, *args: str) -> dict[str, float]:
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", script, *args], capture_output=True, text=True, check=False
    )
    figures = {"wall": time.perf_counter() - start}
    for line in done.stderr.splitlines():
        key, _, value = line.partition(" ")
        if key in ("RSS", "TIME"):
            figures[key] = float(value)
    if "RSS" not in figures:
        raise RuntimeError(done.stderr[-2000:])
    return figures


def cli_table(sizes: list[int], repeat: int) -> None:
    """Medians of ``repeat`` runs of the issue's command line and of the in-process check."""
    print("| children | CLI: median s | peak RSS MiB | in-process check: median s | peak RSS MiB |")
    print("|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            spec = str(scaled_spec(n, Path(folder)))
            argv = ["check", spec, "--formula", CLI_FORMULA, "--backend", "explicit"]
            cli = [_child(_RUN_CLI, *argv) for _ in range(repeat)]
            inner = [_child(_RUN_INPROCESS, spec, CLI_FORMULA) for _ in range(repeat)]
            print(
                f"| {n} | {statistics.median(r['wall'] for r in cli):.2f} | "
                f"{statistics.median(r['RSS'] for r in cli) / 1024:.0f} | "
                f"{statistics.median(r['TIME'] for r in inner):.2f} | "
                f"{statistics.median(r['RSS'] for r in inner) / 1024:.0f} |",
                flush=True,
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--min-n", type=int, default=4)
    parser.add_argument("--max-n", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--general-max-n", type=int, default=20)
    parser.add_argument("--cli", type=int, nargs="+", default=None, metavar="N")
    args = parser.parse_args()
    if args.cli:
        cli_table(args.cli, args.repeat)
        return
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
