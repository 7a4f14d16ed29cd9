"""Muddy children on the symbolic backend (BDDs), beside the explicit one.

All n children are muddy. One run builds the structure from observables, announces the
father's "at least one of you is muddy", then "nobody knows whether they are muddy" until
the muddy children know (n - 1 rounds, the published answer, asserted). The explicit
backend (bitset path of KripkeModel) runs the same loop for small n.

Then the command line: a muddy-children spec for n children, 3 of them muddy (the pattern
of specs/puzzles/muddy_children.epi), is written to a temporary file and
``epistemica check FILE --backend symbolic --formula F`` is timed as a subprocess,
start-up included.

Usage: python benchmarks/symbolic_muddy.py [--sizes 10,20,40,60,100] [--explicit-max-n 20]
       [--repeat 3] [--cli-n 40]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from epistemica.del_ import (
    Atom,
    KnowledgeStructure,
    KnowWhether,
    KripkeModel,
    Not,
    conjunction,
    disjunction,
)

CLI_FORMULA = "[father][nobody_knows][nobody_knows] (K[c1] m1 & K[c2] m2 & K[c3] m3)"


def solve(n: int, backend: type) -> int:
    """Run the puzzle with ``backend`` (a model class); return the "nobody knows" rounds."""
    atoms = [f"m{i}" for i in range(1, n + 1)]
    observes = {f"c{i}": atoms[: i - 1] + atoms[i:] for i in range(1, n + 1)}
    model = backend.from_observables(atoms, observes, designated=atoms)
    # Trees, not text: the timings are model checking, not parsing.
    model = model.announce(disjunction(Atom(a) for a in atoms))
    know = [KnowWhether(f"c{i}", Atom(f"m{i}")) for i in range(1, n + 1)]
    nobody_knows = conjunction(Not(k) for k in know)
    they_know = conjunction(know)
    rounds = 0
    while not model.holds(they_know):
        model = model.announce(nobody_knows)
        rounds += 1
    if rounds != n - 1:
        raise AssertionError(f"{n} muddy children should know after {n - 1} rounds, not {rounds}")
    return rounds


def median_seconds(run, repeat: int) -> float:
    return statistics.median(run_times(run, repeat))


def run_times(run, repeat: int) -> list[float]:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return times


def muddy_spec(n: int, muddy: int = 3) -> str:
    """The text of specs/puzzles/muddy_children.epi scaled to ``n`` children."""
    lines = [f"agents c1..c{n}", f"atoms m1..m{n}"]
    for i in range(1, n + 1):
        seen = ", ".join(f"m{j}" for j in range(1, n + 1) if j != i)
        lines.append(f"observes c{i}: {seen}")
    lines.append("actual {" + ", ".join(f"m{i}" for i in range(1, muddy + 1)) + "}")
    lines.append("action father: public " + " | ".join(f"m{i}" for i in range(1, n + 1)))
    nobody = " & ".join(f"~Kw[c{i}] m{i}" for i in range(1, n + 1))
    lines.append(f"action nobody_knows: public {nobody}")
    return "\n".join(lines) + "\n"


def cli_seconds(n: int, backend: str, repeat: int) -> tuple[float, str]:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"muddy_{n}.epi"
        path.write_text(muddy_spec(n), encoding="utf-8")
        command = [sys.executable, "-m", "epistemica", "check", str(path)]
        command += ["--backend", backend, "--formula", CLI_FORMULA]
        out = ""

        def run() -> None:
            nonlocal out
            done = subprocess.run(command, capture_output=True, text=True, check=False)
            out = (done.stdout + done.stderr).strip().splitlines()[1:2]
            out = out[0].strip() if out else f"exit {done.returncode}"

        return median_seconds(run, repeat), out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="10,20,40,60,100")
    parser.add_argument("--explicit-max-n", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cli-n", type=int, default=40)
    args = parser.parse_args()
    print("| children | states | symbolic: first run s | median s | explicit: median s |")
    print("|---:|---:|---:|---:|---:|")
    for n in (int(x) for x in args.sizes.split(",")):
        symbolic = run_times(lambda n=n: solve(n, KnowledgeStructure), args.repeat)
        explicit = "—"
        if n <= args.explicit_max_n:
            explicit = f"{median_seconds(lambda n=n: solve(n, KripkeModel), args.repeat):.3f}"
        first, middle = symbolic[0], statistics.median(symbolic)
        print(f"| {n} | 2^{n} | {first:.3f} | {middle:.3f} | {explicit} |", flush=True)
    print()
    print(f"CLI, n = {args.cli_n}, 3 muddy: {CLI_FORMULA}")
    for backend in ("symbolic", "auto", "explicit"):
        seconds, line = cli_seconds(args.cli_n, backend, args.repeat)
        print(f"  --backend {backend}: median {seconds:.2f} s ({line})", flush=True)
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(f"  peak RSS of any of these processes: {peak:.0f} MiB")


if __name__ == "__main__":
    main()
