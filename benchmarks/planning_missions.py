"""Today's levels against the planning levels on the shipped missions, mission by mission.

Every mission of ``specs/nested/`` (or ``specs/stress/``) at each level on the same trial
seeds (from 20000, the seeds this project reports), printed as a Markdown table: success %
and the median completion step (a failure counts at the step limit).

Usage::

    python benchmarks/planning_missions.py --suite nested --seeds 20
    python benchmarks/planning_missions.py --suite stress --seeds 10 --levels rules-third,third
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np

from epistemica.mission import load_mission

ROOT = Path(__file__).resolve().parents[1]


def step_limit(path: Path) -> int:
    """The ``steps`` of the mission's ``simulate`` line (60 when it has none)."""
    found = re.search(r"^simulate .*\bsteps (\d+)", path.read_text(), re.MULTILINE)
    return int(found.group(1)) if found else 60


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--suite", choices=("nested", "stress"), default="nested")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=20_000)
    ap.add_argument("--levels", default="rules-third,third,second,third-shared")
    ap.add_argument("--skip", type=int, default=0, help="leave out the first N files")
    ap.add_argument("--stop", type=int, default=None, help="stop before file N (from 0)")
    args = ap.parse_args(argv)
    levels = args.levels.split(",")
    print("| mission | " + " | ".join(f"`{level}`" for level in levels) + " |")
    print("|---|" + "---|" * len(levels))
    for path in sorted((ROOT / "specs" / args.suite).glob("*.epi"))[args.skip : args.stop]:
        mission, steps = load_mission(str(path)), step_limit(path)
        cells = []
        for level in levels:
            seeds = range(args.first_seed, args.first_seed + args.seeds)
            trials = [mission.trial(steps, seed, level) for seed in seeds]
            success = 100 * np.mean([t.success for t in trials])
            cells.append(f"{success:.0f} ({np.median([t.steps for t in trials]):.0f})")
        print(f"| {path.stem} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
