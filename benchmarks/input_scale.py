"""Large input, measured: parsing, deep and wide formulas on both backends, the large
puzzles through the CLI, and ``show --json`` of a 65,536-world model.

    python benchmarks/input_scale.py [--runs 3] [--only parse,limits,puzzles,show]

Prints markdown tables (medians of ``--runs`` runs); docs/performance.md, section "Large
input", has the last figures. Parsing: the fast path (del/language/_fast.py) and lark
alone on the same text, bytes per second and peak Python memory (tracemalloc) per byte of
text. The CLI rows run ``epistemica`` in a fresh process, as a user does.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PUZZLES = ROOT / "specs" / "puzzles"


def _median(run, runs: int, clock=time.perf_counter) -> float:
    times = []
    for _ in range(runs):
        start = clock()
        run()
        times.append(clock() - start)
    return statistics.median(times)


def parsing(runs: int) -> None:
    from epistemica.del_.spec._syntax import parse

    print("| spec | size | fast path (wall) | fast path (CPU) | memory / text | lark alone |")
    print("|---|---:|---:|---:|---:|---:|")
    for name in ("sum_and_product", "drinking_logicians_400", "dining_cryptographers_100"):
        text = (PUZZLES / f"{name}.epi").read_text(encoding="utf-8")
        fast = _median(lambda t=text, n=name: parse(t, n, "start"), runs)
        cpu = _median(lambda t=text, n=name: parse(t, n, "start"), runs, time.process_time)
        tracemalloc.start()
        parse(text, name, "start")
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        slow = _median(lambda t=text, n=name: parse(t, n, "start", fast=False), 1)
        mb = len(text) / 1e6
        print(
            f"| {name} | {len(text) / 1e3:,.0f} kB | {mb / fast:.2f} MB/s | {mb / cpu:.2f} MB/s | "
            f"{peak / len(text):.0f}x | {mb / slow:.3f} MB/s |"
        )


def limits(runs: int) -> None:
    from epistemica.del_ import And, Atom, Know, KnowledgeStructure, KripkeModel, Not

    observes = {"a": ["q"], "b": ["p"]}
    models = {
        "explicit": KripkeModel.from_observables(["p", "q"], observes, designated=["p"]),
        "symbolic": KnowledgeStructure.from_observables(["p", "q"], observes, designated=["p"]),
    }

    def deep_not():
        f = Atom("p")
        for _ in range(10_000):
            f = Not(f)
        return f

    def deep_know():
        f = Atom("q")
        for i in range(10_000):
            f = Know("a" if i % 2 else "b", f)
        return f

    def chain():
        terms = [Atom("p"), Atom("q"), Not(Atom("q"))] * (100_000 // 3)
        f = terms[0]
        for t in terms[1:]:
            f = And(f, t)
        return f

    print("| formula | explicit | symbolic | ratio |")
    print("|---|---:|---:|---:|")
    for label, build in (
        ("~~...~p, 10,000 deep", deep_not),
        ("K[a] K[b] ... q, 10,000 deep", deep_know),
        ("p & q & ~q & ..., 100,000 terms", chain),
    ):
        seconds = {}
        for backend, model in models.items():
            # A fresh formula per run: nothing memoised from the run before.
            seconds[backend] = statistics.median(_timed(model.holds, build()) for _ in range(runs))
        ratio = seconds["symbolic"] / seconds["explicit"]
        print(
            f"| {label} | {seconds['explicit']:.3f} s | {seconds['symbolic']:.3f} s | {ratio:.2f} |"
        )


def _timed(function, argument) -> float:
    start = time.perf_counter()
    function(argument)
    return time.perf_counter() - start


def _cli(*argv: str) -> tuple[float, float]:
    """Wall and CPU seconds (user + system, of the child) of one ``epistemica`` run: on a
    shared machine the CPU time is the steadier figure."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-m", "epistemica", *argv], capture_output=True, check=False
    )
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode not in (0, 1):
        raise SystemExit(f"epistemica {' '.join(argv)} exited {out.returncode}: {out.stderr}")
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return seconds, cpu


def _medians(runs: list[tuple[float, float]]) -> str:
    wall = statistics.median(r[0] for r in runs)
    cpu = statistics.median(r[1] for r in runs)
    return f"{wall:.2f} s | {cpu:.2f} s"


def puzzles(runs: int) -> None:
    print("| spec (epistemica check) | size | wall | CPU |")
    print("|---|---:|---:|---:|")
    for name in ("dining_cryptographers_100", "drinking_logicians_400", "sum_and_product"):
        path = PUZZLES / f"{name}.epi"
        timing = _medians([_cli("check", str(path)) for _ in range(runs)])
        print(f"| {name} | {path.stat().st_size / 1e3:,.0f} kB | {timing} |")


def show(runs: int) -> None:
    lines = ["agents " + ", ".join(f"c{i}" for i in range(1, 17)), "atoms m1..m16"]
    atoms = [f"m{i}" for i in range(1, 17)]
    for i in range(1, 17):
        lines.append(f"observes c{i}: " + ", ".join(a for a in atoms if a != f"m{i}"))
    lines.append("actual {m1, m2}")
    print("| command (muddy children, 16 children: 65,536 worlds) | wall | CPU |")
    print("|---|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "muddy16.epi"
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        for argv in (
            ("show", str(path), "--json"),
            ("show", str(path)),
            ("show", str(path), "--json", "--limit", "100"),
            ("show", str(path), "--backend", "symbolic"),
        ):
            timing = _medians([_cli(*argv) for _ in range(runs)])
            print(f"| `epistemica {' '.join(argv[0:1] + argv[2:])}` | {timing} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--only", default="parse,limits,puzzles,show")
    args = parser.parse_args()
    sections = {"parse": parsing, "limits": limits, "puzzles": puzzles, "show": show}
    for name in args.only.split(","):
        print(f"\n### {name}\n")
        sections[name](args.runs)


if __name__ == "__main__":
    main()
