"""``epistemica run`` on a collaborative mission (``mission collaborative``).

Its trials are short and have their own record (:class:`~epistemica.sim.collaborative.
CollaborativeTrial`), so the study runs in this process, seed by seed for every level,
and prints success with a 95 % Wilson interval and the mean completion step of the
successes; nothing is stored.
"""

from __future__ import annotations

import argparse
import statistics
import time

from epistemica.mission import Mission
from epistemica.sim.collaborative import simulate_collaborative
from epistemica.sim.collaborative_levels import make_collaborative_policy
from epistemica.sim.report import wilson_interval

__all__ = ["run_collaborative"]


def run_collaborative(mission: Mission, args: argparse.Namespace) -> int:
    """Run the study of a collaborative mission; 0."""
    levels = mission.study.levels
    if args.levels is not None:
        levels = tuple(t.strip() for t in args.levels.split(","))
    for level in levels:
        make_collaborative_policy(level)  # unknown names fail before any trial
    trials = 50 if args.paper_scale else (args.trials or mission.study.trials)
    first = mission.study.seed if args.seed is None else args.seed
    seeds = range(first, first + trials)
    started = time.perf_counter()
    print(
        f"{mission.filename}: collaborative, {len(mission.robots)} robots, "
        f"{len(mission.goals)} tasks; {trials * len(levels)} trials (seeds {first}.."
        f"{first + trials - 1})"
    )
    print(f"{'level':<14} {'success':>8}  {'95 % CI':<12} {'mean completion step':>21}")
    for level in levels:
        results = [
            simulate_collaborative(mission.scenario(s), level, s, mission.parameters) for s in seeds
        ]
        done = [t.steps for t in results if t.success]
        low, high = wilson_interval(len(done), trials)
        mean = f"{statistics.mean(done):.1f}" if done else "-"
        print(
            f"{level:<14} {100 * len(done) / trials:>7.0f}%  "
            f"[{100 * low:.0f}, {100 * high:.0f}]{'':<4} {mean:>21}"
        )
    print(f"{trials * len(levels)} trials run in {time.perf_counter() - started:.1f} s")
    return 0
