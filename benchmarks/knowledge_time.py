"""Time a trial spends updating and querying the team's knowledge.

Every public method of :class:`epistemica.sim.engine.knowledge.TeamKnowledge` is wrapped with a
timer (outermost calls only), then stress-suite trials run; the script prints, per trial,
the median over ``--repeats`` runs of the time inside those methods and of the whole trial.
It runs unchanged against an older checkout whose TeamKnowledge kept its own bitsets, so the
two can be compared on one machine, alternately:

    python benchmarks/knowledge_time.py --repeats 5
"""

from __future__ import annotations

import argparse
import functools
import statistics
import time
from pathlib import Path

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.knowledge import TeamKnowledge

ROOT = Path(__file__).resolve().parents[1]
CASES = (
    ("allocation_radius_10", "rules-third", 0),
    ("allocation_hardest_10", "rules-third", 0),
    ("rendezvous_radius_5", "rules-third", 0),
)
_clock = {"inside": 0.0, "depth": 0}


def _timed(method):
    @functools.wraps(method)
    def wrapper(*args, **kwargs):
        if _clock["depth"]:
            return method(*args, **kwargs)
        _clock["depth"] += 1
        started = time.perf_counter()
        try:
            return method(*args, **kwargs)
        finally:
            _clock["inside"] += time.perf_counter() - started
            _clock["depth"] -= 1

    return wrapper


def _instrument() -> None:
    for name in dir(TeamKnowledge):
        value = getattr(TeamKnowledge, name)
        if not name.startswith("_") and callable(value):
            setattr(TeamKnowledge, name, _timed(value))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    _instrument()
    print("| trial | level | seed | knowledge s (median) | trial s (median) | success, steps |")
    print("|---|---|---|---|---|---|")
    for name, level, seed in CASES:
        mission = load_mission(ROOT / "specs" / "stress" / f"{name}.epi")
        scenario, policies = mission.scenario(seed), mission.policies(seed)
        inside, whole = [], []
        for _ in range(args.repeats):
            _clock["inside"] = 0.0
            started = time.perf_counter()
            trial = simulate(scenario, level, seed=seed, policies=policies)
            whole.append(time.perf_counter() - started)
            inside.append(_clock["inside"])
        print(
            f"| {name} | {level} | {seed} | {statistics.median(inside):.3f} | "
            f"{statistics.median(whole):.2f} | {trial.success}, {trial.steps} |"
        )


if __name__ == "__main__":
    main()
