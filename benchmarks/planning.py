"""Planning benchmarks: shortest plan length, states expanded and time per instance.

Runs breadth-first search on every spec of ``specs/planning`` and prints a markdown table
(median wall-clock time of ``--repeat`` runs). ``docs/performance.md`` section "Planning
benchmarks" is this script's output.

Usage: ``python benchmarks/planning.py [--repeat 3] [--max-depth 9]``
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time
from pathlib import Path

from epistemica.del_ import load_spec, plan_with_stats

SPECS = Path(__file__).resolve().parents[1] / "specs" / "planning"

PUBLISHED = {
    "coin_in_the_box_a": 2,
    "coin_in_the_box_b": 4,
    "coin_in_the_box_c": 5,
    "coin_in_the_box_d": 6,
    "selective_communication": 5,
    "selective_communication_depth2": 5,
    "grapevine": 4,
    "cc_2_2_3_pl3": 3,
    "cc_2_2_3_pl4": 4,
    "cc_2_2_3_pl5": 5,
    "cc_2_2_3_pl7": 7,
    "cc_2_2_3_pl8": 8,
    "sally_anne": 3,
    **{f"assembly_line_{n:02d}": 5 for n in range(2, 11)},
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--max-depth", type=int, default=9)
    args = parser.parse_args()
    print(
        f"Python {platform.python_version()}, {platform.machine()}; "
        f"median of {args.repeat} runs; breadth-first search\n"
    )
    print("| instance | published | found | expanded | generated | distinct | time (s) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, published in PUBLISHED.items():
        spec = load_spec(SPECS / f"{name}.epi")
        times, result = [], None
        for _ in range(args.repeat):
            start = time.perf_counter()
            result = plan_with_stats(spec.model, spec.actions, spec.goal, max_depth=args.max_depth)
            times.append(time.perf_counter() - start)
        print(
            f"| {name} | {published} | {result.length} | {result.expanded} | "
            f"{result.generated} | {result.distinct} | {statistics.median(times):.3f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
