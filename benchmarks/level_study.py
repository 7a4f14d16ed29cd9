"""Compare levels on mission files, on the same seeds, with optional parameter changes.

For each mission file and level, runs the trials of the given seeds and prints success
(with a 95 % Wilson interval), mean steps of the successes, and for each pair of levels
the mean paired change in steps on the trials both solve. A level may carry parameter
changes after a colon: ``third:anticipate=true`` (fields of
:class:`epistemica.sim.ActiveParameters`, or controller arguments).

    python benchmarks/level_study.py specs/nested/*_3.epi --seeds 1000-1019 \\
        --levels convention,rules-first,rules-third-shared,rules-third,rules-third:anticipate=true
"""

from __future__ import annotations

import argparse
import math
import statistics
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from epistemica.mission import load_mission
from epistemica.sim import simulate


def _value(text: str):
    low = text.lower()
    if low in ("true", "false"):
        return low == "true"
    if low == "none":
        return None
    if text.isidentifier():  # a word: revision=primacy
        return text
    number = float(text)
    return int(number) if number.is_integer() and "." not in text else number


def _level(spec: str) -> tuple[str, dict]:
    name, _, changes = spec.partition(":")
    options = {}
    for part in filter(None, changes.split(";")):
        key, _, value = part.partition("=")
        options[key.strip()] = _value(value.strip())
    return name, options


def run_one(job: tuple[str, str, int]) -> tuple[str, str, int, bool, int]:
    path, spec, seed = job
    mission = load_mission(path)
    level, changes = _level(spec)
    parameters = mission.parameters.replace(**changes) if changes else mission.parameters
    trial = simulate(
        mission.scenario(seed),
        level,
        seed=seed,
        policies=mission.policies(seed),
        parameters=parameters,
    )
    return path, spec, seed, bool(trial.success), int(trial.steps)


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95 % Wilson interval of ``k`` successes in ``n`` trials, in percent."""
    if n == 0:
        return 0.0, 0.0
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return 100 * (centre - half), 100 * (centre + half)


def _seeds(text: str) -> list[int]:
    first, _, last = text.partition("-")
    return list(range(int(first), int(last or first) + 1))


def run_table(run, missions, levels, seeds, workers) -> dict:
    """``(mission, level) -> {seed: (success, steps)}``, ``run`` on every job in parallel."""
    jobs = [(str(p), lv, s) for p in missions for lv in levels for s in seeds]
    with ProcessPoolExecutor(workers) as pool:
        results = list(pool.map(run, jobs, chunksize=4))
    table: dict[tuple[str, str], dict[int, tuple[bool, int]]] = {}
    for path, spec, seed, success, steps in results:
        table.setdefault((path, spec), {})[seed] = (success, steps)
    return table


def print_table(table: dict, missions, levels, unit: str) -> None:
    """Success with its Wilson interval and the mean steps of the successes, as markdown."""
    print("| mission | " + " | ".join(levels) + " |")
    print("|---|" + "---|" * len(levels))
    for path in missions:
        cells = []
        for lv in levels:
            rows = table[(str(path), lv)]
            k = sum(s for s, _ in rows.values())
            low, high = wilson(k, len(rows))
            steps = [t for s, t in rows.values() if s]
            mean = f", {statistics.mean(steps):.1f}{unit}" if steps else ""
            cells.append(f"{100 * k / len(rows):.0f} % [{low:.0f}, {high:.0f}]{mean}")
        print(f"| {Path(path).stem} | " + " | ".join(cells) + " |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="+")
    parser.add_argument("--seeds", default="0-99", help="first-last (inclusive)")
    parser.add_argument("--levels", default="convention,rules-first,rules-third-shared,rules-third")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    levels = args.levels.split(",")
    seeds = _seeds(args.seeds)
    table = run_table(run_one, args.missions, levels, seeds, args.workers)
    print(f"seeds {args.seeds}\n")
    print_table(table, args.missions, levels, " steps")
    print("\npaired change in steps, last level against each other (trials both solve):")
    last = levels[-1]
    for path in args.missions:
        parts = []
        for lv in levels[:-1]:
            a, b = table[(path, lv)], table[(path, last)]
            both = [s for s in seeds if a[s][0] and b[s][0]]
            if both:
                change = statistics.mean((b[s][1] - a[s][1]) / a[s][1] for s in both)
                parts.append(f"{lv}: {100 * change:+.1f} % over {len(both)}")
        print(f"  {Path(path).stem}: " + "; ".join(parts))


if __name__ == "__main__":
    main()
