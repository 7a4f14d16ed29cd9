"""Wall time of single stress-suite trials at 10 robots (the study's slowest cells).

Each trial is run ``--repeats`` times in this process; the median is printed. Compare two
versions by running the script in each checkout, alternately, on the same machine.

    python benchmarks/stress_speed.py --repeats 3
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from epistemica.mission import load_mission
from epistemica.run import mission_trials
from epistemica.sim.study.sweep import run_trial

ROOT = Path(__file__).resolve().parents[1]
CASES = (
    ("allocation_radius_10", "rules-third", 0),
    ("allocation_hardest_10", "rules-third", 0),
    ("rendezvous_hardest_10", "rules-third", 0),
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print("| trial | level | seed | median s | decision ms | success, steps |")
    print("|---|---|---|---|---|---|")
    for name, level, seed in CASES:
        mission = load_mission(ROOT / "specs" / "stress" / f"{name}.epi")
        spec = mission_trials(mission, [level], 1, seed)[0]
        times = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            row = run_trial(spec)
            times.append(time.perf_counter() - start)
        print(
            f"| {name} | {level} | {seed} | {statistics.median(times):.2f} | "
            f"{row['decision_ms']:.0f} | {row['success']}, {row['steps']} |"
        )


if __name__ == "__main__":
    main()
