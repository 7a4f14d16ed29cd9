"""Benchmark: wall time of one whole-team simulation step (every robot decides once).

For each mission, team size and level, runs ``--trials`` paper-protocol trials (seeds
0..trials-1, rendezvous and allocation with m = n goals; multitask with 20 tasks, 45 at
n = 8) and reports the median over all recorded steps of ``Trial.decision_time`` (the time
the whole team spent deciding in that step), plus trials per second of the whole loop.

Usage: ``python benchmarks/sim_team_step.py [--missions rendezvous,allocation]
[--robots 2,3,5,8,10] [--levels zero,convention,first,third] [--trials 5]``; prints a
markdown table.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from epistemica.sim import Scenario, simulate


def cell(mission: str, n: int, level: str, trials: int) -> tuple[float, float, int]:
    steps, started = [], time.perf_counter()
    for seed in range(trials):
        goals = (45 if n >= 8 else 20) if mission == "multitask" else n
        trial = simulate(Scenario.paper(mission, n, goals, seed=seed), level, seed=seed)
        steps.extend(trial.decision_time.tolist())
        considered = int(np.max(trial.considered)) if trial.steps else 0
    elapsed = time.perf_counter() - started
    return statistics.median(steps) * 1e3, trials / elapsed, considered


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--missions", default="rendezvous,allocation")
    parser.add_argument("--robots", default="2,3,5,8,10")
    parser.add_argument("--levels", default="zero,convention,rules-first,rules-third")
    parser.add_argument("--trials", type=int, default=5)
    args = parser.parse_args()
    print("| mission | robots | level | configurations | team step (ms, median) | trials/s |")
    print("|---|---|---|---|---|---|")
    for mission in args.missions.split(","):
        for n in map(int, args.robots.split(",")):
            for level in args.levels.split(","):
                ms, rate, k = cell(mission, n, level, args.trials)
                print(f"| {mission} | {n} | {level} | {k} | {ms:.2f} | {rate:.2f} |", flush=True)


if __name__ == "__main__":
    main()
