"""Benchmark: one decision of one robot at order 3 over the 32 default controls.

Task allocation with n robots on n goals (n! valid configurations), scenes drawn as in the
paper protocol (30 m x 30 m, goals in [1, 29]^2, starts in [0, 30]^2, sensors uniform over
range/bearing, seeded). The deciding robot is robot 0, timed once as a range robot and
once as a bearing robot (a bearing robot's own viewpoint moves with its control, so its
own belief is recomputed for every candidate; a range robot's is not).

Reported per n: the number of valid configurations, the median and minimum wall time of
one decision (``Controller.decide``, after one warm-up call on the same controller), the
one-off time to build the valid set, the peak of Python allocations during one decision
(tracemalloc) and the process's peak resident set size.

Usage: ``python benchmarks/aif_decision.py [--max-robots 10] [--repeats 21]``; prints a
markdown table.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import sys
import time
import tracemalloc

import numpy as np

from epistemica.aif import Controller, valid_configurations

TARGETS_MS = {5: 2.0, 8: 50.0}


def scene(n: int, seed: int):
    rng = np.random.default_rng(seed)
    goals = rng.uniform(1, 29, (n, 2))
    poses = np.column_stack([rng.uniform(0, 30, (n, 2)), np.zeros(n)])
    sensors = list(rng.choice(["range", "bearing"], n))
    return goals, poses, sensors


def time_decision(ctrl: Controller, poses, repeats: int) -> tuple[float, float, float]:
    ctrl.decide(0, poses)  # warm-up: builds the cached index structures
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        ctrl.decide(0, poses)
        times.append(time.perf_counter() - t0)
    tracemalloc.start()
    ctrl.decide(0, poses)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return statistics.median(times) * 1e3, min(times) * 1e3, peak / 2**20


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-robots", type=int, default=10)
    parser.add_argument("--repeats", type=int, default=21)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)

    rows = []
    for n in range(2, args.max_robots + 1):
        t0 = time.perf_counter()
        configs = valid_configurations("allocation", n, n)
        build_ms = (time.perf_counter() - t0) * 1e3
        goals, poses, sensors = scene(n, args.seed + n)
        repeats = args.repeats if configs.shape[0] < 100_000 else 5
        cells = []
        for own in ("range", "bearing"):
            team = [own, *sensors[1:]]
            ctrl = Controller(goals, team, configs, order=3)
            cells.append((time_decision(ctrl, poses, repeats), len(ctrl.perspectives(0))))
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KiB -> MiB on Linux
        rows.append((n, configs.shape[0], build_ms, cells, rss))
        (r_med, r_min, r_peak), _ = cells[0]
        (b_med, b_min, b_peak), _ = cells[1]
        print(f"n={n}: range {r_med:.2f} ms, bearing {b_med:.2f} ms", file=sys.stderr)

    print(
        "| robots | valid configurations | perspectives | range robot: median (min) ms "
        "| bearing robot: median (min) ms | target ms | peak alloc. per decision MiB "
        "| build set ms | process peak RSS MiB |"
    )
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for n, k, build_ms, cells, rss in rows:
        (r_med, r_min, r_peak), persp = cells[0]
        (b_med, b_min, b_peak), _ = cells[1]
        target = TARGETS_MS.get(n)
        print(
            f"| {n} | {k:,} | {persp} | {r_med:.2f} ({r_min:.2f}) | {b_med:.2f} ({b_min:.2f}) "
            f"| {'<= ' + format(target, 'g') if target else ''} | {max(r_peak, b_peak):.1f} "
            f"| {build_ms:.1f} | {rss:.0f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
