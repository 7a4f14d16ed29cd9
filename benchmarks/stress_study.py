"""The stress-suite study (issue 11): every variant, mission and team size, every level.

Runs the mission files of specs/stress/ (written by benchmarks/stress_suite.py) through the
sweep machinery into one resumable SQLite file, then prints, per mission and variant, the
success rate with its 95 % Wilson interval and the mean steps of the successes. The
reported seeds are 0..S-1; the controller's parameters were chosen on seeds 1000-1039
(docs/aif.md), and nothing here was tuned on the reported seeds. Cells read
"rate [95 % interval] (mean steps of the successes)".

    python benchmarks/stress_study.py --sizes 2,3,5 --trials 50 --out runs/stress.sqlite
    python benchmarks/stress_study.py --sizes 2,3,5 --trials 50 --out runs/stress.sqlite --table
"""

from __future__ import annotations

import argparse
from pathlib import Path

from epistemica.mission import load_mission
from epistemica.run import mission_trials, run_study
from epistemica.sim.study.report import summarise, wilson_interval
from epistemica.sim.study.store import ResultStore

ROOT = Path(__file__).resolve().parents[1]
LEVELS = ("convention", "rules-first", "rules-third", "rules-third-shared", "rules-third-unpruned")


def files(sizes, match: str = "", skip=()):
    out = []
    for mission in ("rendezvous", "allocation"):
        for path in sorted((ROOT / "specs" / "stress").glob(f"{mission}_*.epi")):
            if int(path.stem.rsplit("_", 1)[1]) not in sizes or match not in path.stem:
                continue
            if not any(part in path.stem for part in skip):
                out.append(path)
    return out


def table(rows, sizes, trials: int, levels=LEVELS) -> str:
    cells = summarise(rows)
    by = {}
    for c in cells:
        spec = c.options.split('"spec": "')[1].split('"')[0]
        mission, rest = spec.split("_", 1)
        variant = rest.rsplit("_", 1)[0]
        by[(mission, variant, c.robots, c.reasoning)] = c
    lines = []
    for mission in ("rendezvous", "allocation"):
        variants = sorted({k[1] for k in by if k[0] == mission})
        head = "| variant | robots | " + " | ".join(levels) + " |"
        lines += [f"\n**{mission}**\n", head, "|---|---|" + "---|" * len(levels)]
        for variant in variants:
            for n in sizes:
                row = [variant, str(n)]
                for level in levels:
                    c = by.get((mission, variant, n, level))
                    if c is None:
                        row.append("–")
                        continue
                    lo, hi = wilson_interval(c.successes, c.trials)
                    part = "" if c.trials >= trials else f", {c.trials} trials"
                    steps = "–" if c.successes == 0 else f"{c.mean_steps:.0f}"
                    row.append(
                        f"{100 * c.rate:.0f} [{100 * lo:.0f}, {100 * hi:.0f}] ({steps}{part})"
                    )
                lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="2,3,5")
    parser.add_argument("--trials", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default="runs/stress.sqlite")
    parser.add_argument(
        "--also", action="append", default=[], help="with --table: more result files to read"
    )
    parser.add_argument("--table", action="store_true", help="only print the table")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--match", default="", help="run only files whose name contains it")
    parser.add_argument("--levels", default=",".join(LEVELS), help="levels to run or tabulate")
    parser.add_argument(
        "--skip", default="", help="comma-separated: leave out files whose name contains one"
    )
    args = parser.parse_args()
    sizes = [int(x) for x in args.sizes.split(",")]
    levels = tuple(args.levels.split(","))
    skip = tuple(filter(None, args.skip.split(",")))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    with ResultStore(args.out, resume=True) as store:
        specs = []
        for path in files(sizes, args.match if not args.table else "", skip):
            specs += mission_trials(load_mission(path), levels, args.trials, args.seed)
        if not args.table:
            ran, skipped = run_study(specs, store, workers=args.workers)
            print(f"{ran} trials run, {skipped} already stored")
        ids = {s.id for s in specs}
        rows = [r for r in store.rows() if r["id"] in ids]
    for extra in args.also if args.table else ():
        with ResultStore(extra, resume=True) as more:
            rows += [r for r in more.rows() if r["id"] in ids]
    print(table(rows, sizes, args.trials, levels))


if __name__ == "__main__":
    main()
