"""The generator's targets: 1,000 missions per family written in at most 10 s, and every one
compiles, passes ``epistemica check`` and runs a trial without error.

Writes ``--count`` missions of each family (generator seeds 0 ..) into a fresh temporary
folder and times it, then compiles each file as ``epistemica check`` does (its claims,
if any) and runs the first ``--steps`` steps of trial seed 0 at ``--level`` (by default the
rules' level of the kind, ``rules-third`` or ``rules``: the level with the most
machinery), on ``--workers`` processes; prints per family the time to write, the time to
compile and run, and every file that failed (none expected).

    python benchmarks/generated_missions.py                  # 1,000 per family, 20 steps
    python benchmarks/generated_missions.py --count 50 --steps 400 --workers 2
"""

from __future__ import annotations

import argparse
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from epistemica.cli import main as cli
from epistemica.generate import FAMILIES, Options, generate
from epistemica.mission import load_mission
from epistemica.sim.policies.levels import rules_level

GOAL_OPTIONS = Options(obstacles=0.25, discs=0.25)


def check_one(job: tuple[str, str | None, int]) -> str | None:
    """None if the file compiles, its claims pass and its trial runs; else the error."""
    path, level, steps = job
    try:
        mission = load_mission(path)
        if mission.checks and cli(["check", path]) != 0:
            return f"{path}: check failed"
        trial = mission.trial(steps, 0, level or rules_level(mission.kind))
        if trial.steps < 1:
            return f"{path}: no step ran"
    except Exception as exc:  # the benchmark reports every error, whatever it is
        return f"{path}: {type(exc).__name__}: {exc}"
    return None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--level", default=None, help="default: the kind's rules level")
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for family in FAMILIES:
            options = Options() if family == "collaborative" else GOAL_OPTIONS
            started = time.perf_counter()
            paths = generate(family, args.count, 0, Path(tmp) / family, options)
            wrote = time.perf_counter() - started
            started = time.perf_counter()
            jobs = [(str(p), args.level, args.steps) for p in paths]
            with ProcessPoolExecutor(args.workers) as pool:
                errors = [e for e in pool.map(check_one, jobs, chunksize=20) if e]
            ran = time.perf_counter() - started
            failed += len(errors)
            print(f"{family}: wrote {len(paths)} in {wrote:.2f} s; compiled and ran "
                  f"{len(paths)} trials ({args.steps} steps, {args.level or 'rules'}) "
                  f"in {ran:.0f} s; "
                  f"{len(errors)} failed", flush=True)  # fmt: skip
            for e in errors:
                print("  " + e)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
