"""Time collaborative trials of this checkout against another, alternating on one machine.

Each round runs, in a fresh process per interpreter, the same trials (a mission file, a level,
seeds) through :meth:`epistemica.mission.Mission.trial`, which both versions have, and reports
the wall time of the trials alone (compiling the file and a short warm-up trial excluded).
The interpreters alternate round by round, so that a change in the machine's load falls on
both; the table gives each one's median over the rounds and the ratio of the medians.

    python benchmarks/collaborative_speed.py --other /path/to/old/checkout/.venv/bin/python

Without ``--other`` it times this checkout alone.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_TIMED = """
import sys, time
from epistemica.mission import load_mission
path, level, steps, seeds = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
mission = load_mission(path)
mission.trial(5, 0, level)
started = time.perf_counter()
for seed in range(*map(int, seeds.split("-"))):
    mission.trial(steps, seed, level)
print(time.perf_counter() - started)
"""


def _seconds(python: str, args: argparse.Namespace) -> float:
    first, last = args.seeds
    command = [python, "-c", _TIMED, str(args.mission), args.level, str(args.steps)]
    out = subprocess.run(
        [*command, f"{first}-{last + 1}"], capture_output=True, text=True, check=True, cwd="/"
    )
    return float(out.stdout.strip().splitlines()[-1])


def _seeds(text: str) -> tuple[int, int]:
    first, _, last = text.partition("-")
    return int(first), int(last or first)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--other", help="the Python interpreter of the other checkout")
    parser.add_argument("--mission", default=ROOT / "specs" / "collaborative" / "tasks_5.epi")
    parser.add_argument("--level", default="rules")
    parser.add_argument("--steps", type=int, default=400, help="step limit (default 400)")
    parser.add_argument("--seeds", type=_seeds, default=(0, 9), help="e.g. 0-9")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    pythons = {"this checkout": sys.executable}
    if args.other:
        pythons["other"] = args.other
    times: dict[str, list[float]] = {name: [] for name in pythons}
    for round_ in range(args.rounds):
        order = list(pythons.items())
        if round_ % 2:
            order.reverse()
        for name, python in order:
            times[name].append(_seconds(python, args))
    seeds = f"seeds {args.seeds[0]}-{args.seeds[1]}"
    print(f"{Path(args.mission).name} at {args.level}, {seeds}, {args.rounds} rounds")
    for name, values in times.items():
        runs = ", ".join(f"{v:.2f}" for v in values)
        print(f"{name:>14}: median {statistics.median(values):.2f} s ({runs})")
    if args.other:
        ratio = statistics.median(times["this checkout"]) / statistics.median(times["other"])
        print(f"this checkout takes {ratio:.2f}x the other's time ({(1 - ratio) * 100:.1f} % less)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
