"""Benchmark: what the environment (epistemica.sim.engine.env) costs over simulate for one trial.

For each mission file, level and seed, the same trial is run twice: by
``simulate(scenario, level, seed)``, and through ``MissionEnv(scenario)`` (built once, then
``reset(seed=seed)`` and stepped to the end) with every agent given
``env.level_actions(level)`` (the environment then runs exactly simulate's trial:
tests/sim/test_env.py). Both include the level's decisions; the environment adds building
each agent's observation dict, the reward and the PettingZoo bookkeeping. Each timing is
the median CPU time (``time.process_time``, so that other processes' load counts less) of
``--repeats`` runs, the two ways interleaved, after one warm-up; the overhead of a cell is
``sum(env medians) / sum(simulate medians) - 1`` over its seeds. The target is 20 %.

Goal, multitask and collaborative missions (``specs/collaborative/tasks_3.epi`` and
``tasks_5.epi`` at ``convention`` and ``rules``).

Usage: ``python benchmarks/env_overhead.py [--seeds 3] [--repeats 7] [--only NAME]``; prints
a markdown table.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.env import MissionEnv

ROOT = Path(__file__).resolve().parents[1]
GOAL_LEVELS = ("zero", "convention", "rules-third")
#: Mission file -> the levels run on it (a collaborative mission has its own levels).
MISSIONS = {
    "rendezvous.epi": GOAL_LEVELS,
    "events/door_closes.epi": GOAL_LEVELS,
    "nested/relocated_5.epi": GOAL_LEVELS,
    "multi_task.epi": GOAL_LEVELS,
    "collaborative/tasks_3.epi": ("convention", "rules"),
    "collaborative/tasks_5.epi": ("convention", "rules"),
}
TARGET = 0.20


def _through_env(env: MissionEnv, level: str, seed: int) -> int:
    env.reset(seed=seed)
    steps = 0
    while env.agents:
        env.step(env.level_actions(level))
        steps += 1
    return steps


def _medians(runs, repeats: int) -> list[float]:
    """Median CPU seconds of each of ``runs``, interleaved so that both see the same load."""
    times: list[list[float]] = [[] for _ in runs]
    for run in runs:
        run()  # warm-up
    for _ in range(repeats):
        for run, out in zip(runs, times, strict=True):
            started = time.process_time()
            run()
            out.append(time.process_time() - started)
    return [statistics.median(t) for t in times]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--only", default="", help="run the missions whose file name has this")
    args = parser.parse_args()
    print("| mission | level | steps | simulate (ms) | env (ms) | ms per step added | overhead |")
    print("|---|---|---:|---:|---:|---:|---:|")
    worst = 0.0
    for name, levels in MISSIONS.items():
        if args.only not in name:
            continue
        mission = load_mission(ROOT / "specs" / name)
        for level in levels:
            sim_total = env_total = 0.0
            steps = 0
            for seed in range(args.seeds):
                s = mission.scenario(seed)
                env = MissionEnv(s)  # built once, as a learner would; reset every episode

                def by_simulate(s=s, level=level, seed=seed):
                    return simulate(s, level, seed)

                def by_env(env=env, level=level, seed=seed):
                    return _through_env(env, level, seed)

                sim, through = _medians([by_simulate, by_env], args.repeats)
                sim_total, env_total = sim_total + sim, env_total + through
                steps += _through_env(env, level, seed)
            overhead = env_total / sim_total - 1
            worst = max(worst, overhead)
            added = (env_total - sim_total) / steps * 1e3
            print(
                f"| {name} | {level} | {steps} | {sim_total * 1e3:.1f} | {env_total * 1e3:.1f} "
                f"| {added:.3f} | {overhead:+.1%} |"
            )
    print(f"\nworst overhead {worst:+.1%} (target {TARGET:.0%})")
    return 0 if worst <= TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
