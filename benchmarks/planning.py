"""Planning benchmarks: shortest plan length, states expanded and time per instance.

Runs breadth-first search on every spec of ``specs/planning`` and prints a markdown table
(median wall-clock time of ``--repeat`` runs). ``docs/performance.md`` section "Planning
benchmarks" is this script's output.

With ``--irrelevant K``, every spec is planned twice, as shipped and with ``K`` more
atoms that no action or goal mentions and no agent observes (each doubles the worlds of
the initial state), and the table gives both times, their ratio and whether the plans are
the same; ``--agents J`` also adds ``J`` agents that observe nothing and that no formula
names; ``--only NAME ...`` restricts the specs (for slow baselines); ``--cli`` times the
command line ``epistemica plan FILE`` instead (a fresh process per run: load, search,
validation and printing), and compares the plans it prints.

Usage: ``python benchmarks/planning.py [--repeat 3] [--max-depth 9] [--irrelevant 10]``
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import subprocess
import sys
import tempfile
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


def with_irrelevant_atoms(path: Path, k: int, folder: Path, agents: int = 0) -> Path:
    """A copy of the spec with ``k`` more atoms (after its first ``atoms`` line) and
    ``agents`` more agents that observe nothing and that no formula names."""
    lines = path.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("atoms "))
    lines.insert(at + 1, "atoms " + ", ".join(f"irrelevant{j}" for j in range(k)))
    if agents:
        at = next(i for i, line in enumerate(lines) if line.startswith("agents "))
        lines[at] += ", " + ", ".join(f"bystander{j}" for j in range(agents))
    out = folder / path.name
    out.write_text("\n".join(lines) + "\n")
    return out


def timed_plan(path: Path, repeat: int, max_depth: int):
    """Median seconds of ``repeat`` breadth-first searches, the result and the world count."""
    spec = load_spec(path)
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = plan_with_stats(spec.model, spec.actions, spec.goal, max_depth=max_depth)
        times.append(time.perf_counter() - start)
    return statistics.median(times), result, spec.model.n_worlds


def timed_cli(path: Path, repeat: int, max_depth: int):
    """Median seconds of ``repeat`` runs of ``epistemica plan FILE --json`` (fresh
    processes), the result (an object with the plan) and the world count."""
    command = [sys.executable, "-m", "epistemica", "plan", str(path), "--json"]
    command += ["--max-depth", str(max_depth)]
    times, out = [], ""
    for _ in range(repeat):
        start = time.perf_counter()
        out = subprocess.run(command, capture_output=True, text=True, check=False).stdout
        times.append(time.perf_counter() - start)
    plan = json.loads(out)["plan"]
    return statistics.median(times), argparse.Namespace(plan=plan), load_spec(path).model.n_worlds


def irrelevant_table(
    names: list[str], k: int, repeat: int, max_depth: int, agents: int = 0, cli: bool = False
) -> None:
    """Planning time as shipped and with ``k`` irrelevant atoms; the plans must agree."""
    more_agents = f" +{agents} agents" if agents else ""
    print(
        f"| instance | worlds | time (s) | worlds +{k} atoms{more_agents} | time (s) | ratio "
        "| same plan |"
    )
    print("|---|---:|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name in names:
            path = SPECS / f"{name}.epi"
            timed = timed_cli if cli else timed_plan
            base, plain, worlds = timed(path, repeat, max_depth)
            bigger = with_irrelevant_atoms(path, k, Path(folder), agents)
            more, padded, more_worlds = timed(bigger, repeat, max_depth)
            print(
                f"| {name} | {worlds:,} | {base:.4f} | {more_worlds:,} | {more:.4f} | "
                f"{more / base:.2f} | {'yes' if plain.plan == padded.plan else 'NO'} |",
                flush=True,
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--max-depth", type=int, default=9)
    parser.add_argument("--irrelevant", type=int, default=0, metavar="K")
    parser.add_argument("--agents", type=int, default=0, metavar="J")
    parser.add_argument("--only", nargs="*", default=None, metavar="NAME")
    parser.add_argument("--cli", action="store_true", help="time `epistemica plan` processes")
    args = parser.parse_args()
    names = args.only or list(PUBLISHED)
    if args.irrelevant:
        print(
            f"Python {platform.python_version()}, {platform.machine()}; "
            f"median of {args.repeat} runs; breadth-first search"
            + ("; `epistemica plan FILE` in a fresh process per run\n" if args.cli else "\n")
        )
        irrelevant_table(names, args.irrelevant, args.repeat, args.max_depth, args.agents, args.cli)
        return
    print(
        f"Python {platform.python_version()}, {platform.machine()}; "
        f"median of {args.repeat} runs; breadth-first search\n"
    )
    print("| instance | published | found | expanded | generated | distinct | time (s) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name in names:
        published = PUBLISHED[name]
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
