"""Steps per second: the single environment against the vectorised one.

``MissionEnv`` (one trial, a dict of actions per step) against ``VectorMissionEnv`` at
``--copies`` copies (one array of actions per step, ``copies`` environment steps per call),
on the published rendezvous family (3 robots, 3 goals, random actions, trials restarting
as they end). Median of ``--repeats`` interleaved runs of ``--steps`` environment steps each.

    python benchmarks/vector_env.py --copies 1 8 64 --steps 20000 --repeats 5
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from epistemica.sim.engine.env import MissionEnv
from epistemica.sim.engine.env_registry import PaperFamily
from epistemica.sim.engine.vector_env import VectorMissionEnv


def single(steps: int, rng: np.random.Generator) -> float:
    env = MissionEnv(PaperFamily("rendezvous", 3, 3))
    env.reset(seed=0)
    started = time.perf_counter()
    for _ in range(steps):
        if not env.agents:
            env.reset()
        env.step({a: rng.uniform([0.0, -1.0], [1.0, 1.0]) for a in env.agents})
    return steps / (time.perf_counter() - started)


def vectorised(steps: int, copies: int, rng: np.random.Generator) -> float:
    env = VectorMissionEnv(PaperFamily("rendezvous", 3, 3), num_envs=copies)
    env.reset(seed=0)
    calls = max(1, steps // copies)
    started = time.perf_counter()
    for _ in range(calls):
        env.step(rng.uniform([0.0, -1.0], [1.0, 1.0], size=(copies, 3, 2)))
    return calls * copies / (time.perf_counter() - started)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copies", type=int, nargs="+", default=[1, 8, 64])
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    runs: dict[str, list[float]] = {"single": []}
    for _ in range(args.repeats):
        runs["single"].append(single(args.steps, rng))
        for copies in args.copies:
            runs.setdefault(f"vector x{copies}", []).append(vectorised(args.steps, copies, rng))
    base = statistics.median(runs["single"])
    print(f"{'environment':<12} {'steps/s (median)':>17} {'vs single':>10}")
    for name, values in runs.items():
        rate = statistics.median(values)
        print(f"{name:<12} {rate:>17,.0f} {rate / base:>9.1f}x")


if __name__ == "__main__":
    main()
