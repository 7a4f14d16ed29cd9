"""Pruning by observed events in the multi-task mission: 8 robots, 45 tasks (issue 10).

Compares, on the same seeds, the convention, third order with DEL pruning (each robot
drops the configurations that use tasks it saw done, or was shown done by who saw it) and
third order without it (`third-unpruned`: it ignores those events), with the upper-level
tasking in all three; and reports how many configurations a decision would range over with
neither tasking nor pruning (counted, not enumerated). Sensing range 10 m: only robots near
the one completing a task see it.

    python benchmarks/pruning_multitask.py --seeds 0..9
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from epistemica.sim import Scenario, simulate
from epistemica.sim.study.report import wilson_interval


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, default=8)
    parser.add_argument("--tasks", type=int, default=45)
    parser.add_argument("--seeds", default="0..9")
    parser.add_argument("--levels", default="convention,rules-third,rules-third-unpruned")
    args = parser.parse_args()
    low, _, high = args.seeds.partition("..")
    seeds = range(int(low), int(high or low) + 1)
    n, m = args.robots, args.tasks
    full = math.perm(m, n)
    print(
        f"{n} robots, {m} tasks: without tasking or pruning a decision ranges over "
        f"{full:.3e} configurations ({full * n / 2**40:.0f} TiB as uint8 rows)"
    )
    print(
        "| level | success [95 % CI] | mean completion step | configs per decision "
        "(mean, max) | team step ms (median) |"
    )
    print("|---|---|---|---|---|")
    for level in args.levels.split(","):
        done, completion, considered, peak, times = 0, [], [], 0, []
        for seed in seeds:
            s = Scenario.paper("multitask", n, m, seed, sensing_range=10.0,
                               events=(("complete", "nearby"),))  # fmt: skip
            started = time.perf_counter()
            t = simulate(s, level, seed=seed)
            _ = time.perf_counter() - started
            done += t.success
            completion.append(t.completion_step if t.success else s.max_steps)
            considered.append(float(t.considered.mean()))
            peak = max(peak, int(t.considered.max()))
            times.append(1e3 * float(np.median(t.decision_time)))
        lo, hi = wilson_interval(done, len(seeds))
        print(
            f"| {level} | {done}/{len(seeds)} [{100 * lo:.0f}, {100 * hi:.0f}] % | "
            f"{np.mean(completion):.1f} | {np.mean(considered):.0f}, {peak} | "
            f"{np.median(times):.1f} |"
        )


if __name__ == "__main__":
    main()
