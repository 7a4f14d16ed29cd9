"""Cost of one planning decision per robot, at 3, 5 and 8 robots, against the one-step
controller: closed-loop trials of the paper protocol, each step timed around the team's
policy call and divided by the team's size.

Target (issue 37): one decision <= 20 ms per robot at 8 robots on one core (a 10 Hz loop).
Medians over the trials' steps; several seeds per cell.

Usage::

    python benchmarks/planning_cost.py            # about a minute
    python benchmarks/planning_cost.py --seeds 2  # quicker
"""

from __future__ import annotations

import argparse

import numpy as np

from epistemica.sim import Scenario, simulate
from epistemica.sim.policies.levels import make_policy

LEVELS = ("rules-third", "first", "second", "third", "third-wait")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--kinds", default="rendezvous,allocation")
    args = ap.parse_args(argv)
    print("| kind | robots | level | median ms per robot-decision | p90 | steps timed |")
    print("|---|---|---|---|---|---|")
    for kind in args.kinds.split(","):
        for n in (3, 5, 8):
            for level in LEVELS:
                times = []
                for seed in range(2000, 2000 + args.seeds):
                    scenario = Scenario.paper(kind, n, n, seed=seed)
                    trial = simulate(scenario, make_policy(level), seed=seed)
                    times.append(np.asarray(trial.decision_time) / n)
                t = np.concatenate(times) * 1e3
                print(f"| {kind} | {n} | {level} | {np.median(t):.2f} | "
                      f"{np.percentile(t, 90):.2f} | {t.size} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
