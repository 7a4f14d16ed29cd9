"""The generated benchmark: every level on the same generated missions and trial seeds.

Missions come from :mod:`epistemica.generate` (docs/generator.md); a *split* names the
generator seeds and the trial seeds. The **tuning** split may be looked at while choosing
anything; the **locked** split is run only to report (docs/results.md). Trials go through
the sweep machinery into one resumable SQLite results file per split (a mission's trial id
hashes its text, level and seed, so a run stopped at any moment resumes where it was), then
per family: success with 95 % Wilson intervals, median and mean completion (a failure counts
at its step limit), and the rules (``rules-third``; ``rules`` on collaborative missions)
against every other level, paired on the same trials, with
95 % bootstrap intervals over missions and win/tie/loss counts (benchmarks/paired_tables.py).

    python benchmarks/generated_benchmark.py --split tuning --missions 20 --workers 2
    python benchmarks/generated_benchmark.py --split locked --workers 2      # the reported run
    python benchmarks/generated_benchmark.py --split locked --tables-only    # tables from the file
    python benchmarks/generated_benchmark.py --split locked --missions 3 --trial-seeds 1 \\
        --out runs/quick.sqlite                              # a prefix of the split (CI)
    python benchmarks/generated_benchmark.py --split tuning --families collaborative \\
        --missions 20 --trial-seeds 1 --collaborative-levels third,recruit,rules-first,oracle
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np
from paired_tables import success_table, versus_table

from epistemica.generate import FAMILIES, Options, mission_text
from epistemica.mission import parse_mission
from epistemica.run import mission_trials, run_study
from epistemica.sim.study.store import ResultStore, read_rows


class Split(NamedTuple):
    first_mission: int  # generator seed of mission 0
    missions: int  # generator seeds first_mission .. first_mission + missions - 1
    trial_seeds: tuple[int, ...]


SPLITS = {
    "tuning": Split(0, 200, (0, 1)),
    "locked": Split(1_000_000, 200, (30_000, 30_001)),
}
GOAL_LEVELS = (
    "convention",
    "convention+rules",
    "rules-first",
    "rules-third-shared",
    "rules-third",
)
COLLABORATIVE_LEVELS = (
    "convention",
    "rules-first",
    "recruit",
    "convention+rules",
    "rules-shared",
    "rules",
)
#: Goal families draw walls and disc robots in a quarter of their missions each.
GOAL_OPTIONS = Options(obstacles=0.25, discs=0.25)


def family_levels(family: str) -> tuple[str, ...]:
    return COLLABORATIVE_LEVELS if family == "collaborative" else GOAL_LEVELS


def reference(family: str) -> str:
    """The level the others are paired against: the rules' (``rules-third``, ``rules``)."""
    return "rules" if family == "collaborative" else "rules-third"


def use_goal_levels(levels: str | None) -> None:
    """``--levels``: the goal families' levels (``rules-third`` stays the reference)."""
    global GOAL_LEVELS
    if levels:
        GOAL_LEVELS = tuple(dict.fromkeys([reference("goal"), *levels.split(",")]))


def use_collaborative_levels(levels: str | None) -> None:
    """``--collaborative-levels``: the collaborative family's levels (``rules`` stays the
    reference), e.g. ``third,recruit,rules-first,oracle``."""
    global COLLABORATIVE_LEVELS
    if levels:
        COLLABORATIVE_LEVELS = tuple(
            dict.fromkeys([reference("collaborative"), *levels.split(",")])
        )


#: ``--policy``: ``policy NAME VALUE`` lines added to every mission (tuning runs).
POLICY_LINES: tuple[str, ...] = ()


def family_options(family: str) -> Options:
    return Options() if family == "collaborative" else GOAL_OPTIONS


#: Families whose trials do not depend on the trial seed: a collaborative mission fixes
#: every position and its sensing is exact, so a second seed would replay the first and
#: count every trial twice (tests/test_generated_benchmark.py checks it stays so).
SEEDLESS = frozenset({"collaborative"})


def family_seeds(family: str, split: Split, seeds: int) -> tuple[int, ...]:
    """The trial seeds a family runs: the first ``seeds`` of the split, one if seedless."""
    return split.trial_seeds[: min(seeds, 1) if family in SEEDLESS else seeds]


def interleaved(families, split: Split, missions: int, seeds: int) -> list:
    """The trials of every family, mission by mission (mission k of each family before
    mission k + 1 of any), so that a run stopped early leaves a prefix of each family."""
    per = {f: trials(f, split, missions, seeds) for f in families}
    out = []
    for k in range(missions):
        for specs in per.values():
            step = len(specs) // missions
            out.extend(specs[k * step : (k + 1) * step])
    return out


def trials(family: str, split: Split, missions: int, seeds: int) -> list:
    """Every trial of ``family`` on the first ``missions`` missions and ``seeds`` trial
    seeds of ``split``, every level on each."""
    out = []
    for k in range(missions):
        seed = split.first_mission + k
        text = mission_text(family, seed, family_options(family))
        text += "".join(f"policy {line}\n" for line in POLICY_LINES)
        mission = parse_mission(text, f"{family}_{seed:06d}.epi")
        for t in family_seeds(family, split, seeds):
            out.extend(mission_trials(mission, family_levels(family), 1, t))
    return out


def collect(path: Path, family: str, split: Split, missions: int, seeds: int) -> dict:
    """``{(mission, trial seed): {level: (success, steps)}}`` of the file's rows, for the
    longest prefix of the split's missions whose every trial (seed and level) is stored: a
    run stopped early reports the missions it finished in order, never a selection."""
    names = [f"{family}_{split.first_mission + k:06d}" for k in range(missions)]
    out: dict = {}
    for row in read_rows(path):
        name = json.loads(row["options"]).get("spec")
        if name in names and row["seed"] in family_seeds(family, split, seeds):
            out.setdefault((name, row["seed"]), {})[row["reasoning"]] = (
                int(row["success"]),
                int(row["steps"]),
            )
    levels = set(family_levels(family))
    for name in names:
        keys = [(name, t) for t in family_seeds(family, split, seeds)]
        if not all(set(out.get(k, ())) >= levels for k in keys):
            kept = set(names[: names.index(name)])
            return {k: r for k, r in out.items() if k[0] in kept}
    return out


def tables(path: Path, families, split_name: str, missions: int, seeds: int) -> str:
    split = SPLITS[split_name]
    rng = np.random.default_rng(20_261_128)  # the bootstrap's resamples
    lines = []
    for family in families:
        rows = collect(path, family, split, missions, seeds)
        done = len({k[0] for k in rows})
        last = split.first_mission + done - 1
        left = "" if done == missions else f" (the first {done} of {missions}: the run stopped)"
        lines += [
            f"### {family}",
            "",
            f"Split `{split_name}`: generator seeds {split.first_mission}–{last}{left}, trial "
            f"seeds {', '.join(map(str, family_seeds(family, split, seeds)))}"
            f"{' (its trials do not depend on the seed)' if family in SEEDLESS else ''}; "
            f"{len(rows)} trials per level.",
            "",
            *success_table(rows, family_levels(family)),
            "",
            *versus_table(rows, reference(family), family_levels(family), rng),
            "",
        ]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--split", choices=sorted(SPLITS), required=True)
    ap.add_argument("--families", default=",".join(FAMILIES), help="comma-separated")
    ap.add_argument("--missions", type=int, default=None, help="the first N of the split")
    ap.add_argument("--trial-seeds", type=int, default=None, help="the first K of the split")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--out", default=None, help="results file (default runs/generated-SPLIT)")
    ap.add_argument("--tables", default=None, help="also write the tables to this file")
    ap.add_argument("--tables-only", action="store_true", help="read the file, run nothing")
    ap.add_argument("--levels", default=None, help="goal families' levels, comma-separated")
    ap.add_argument(
        "--collaborative-levels", default=None, help="the collaborative family's levels"
    )
    ap.add_argument(
        "--policy", action="append", default=[], metavar="NAME=VALUE",
        help="a parameter for every mission (a `policy NAME VALUE` line), to tune",
    )  # fmt: skip
    args = ap.parse_args(argv)
    global POLICY_LINES
    POLICY_LINES = tuple(item.replace("=", " ", 1) for item in args.policy)
    use_goal_levels(args.levels)
    use_collaborative_levels(args.collaborative_levels)
    split = SPLITS[args.split]
    missions = split.missions if args.missions is None else args.missions
    seeds = len(split.trial_seeds) if args.trial_seeds is None else args.trial_seeds
    families = [f.strip() for f in args.families.split(",")]
    bad = [f for f in families if f not in FAMILIES]
    if bad or not 1 <= missions <= split.missions or not 1 <= seeds <= len(split.trial_seeds):
        print(f"error: families in {list(FAMILIES)}, --missions 1..{split.missions}, "
              f"--trial-seeds 1..{len(split.trial_seeds)}", file=sys.stderr)  # fmt: skip
        return 2
    path = Path(args.out or f"runs/generated-{args.split}.sqlite")
    path.parent.mkdir(parents=True, exist_ok=True)
    if not args.tables_only:
        with ResultStore(str(path), resume=True) as store:
            for family in families:
                started, done = time.perf_counter(), 0
                specs = trials(family, split, missions, seeds)
                total = len(specs)

                def progress(_row, family=family, started=started, total=total):
                    nonlocal done
                    done += 1
                    if done % 200 == 0:
                        took = time.perf_counter() - started
                        print(f"  {family}: {done}/{total} trials, {took:.0f} s", flush=True)

                ran, skipped = run_study(specs, store, workers=args.workers, progress=progress)
                took = time.perf_counter() - started
                print(f"{family}: ran {ran}, had {skipped}, {took:.0f} s wall", flush=True)
    text = tables(path, families, args.split, missions, seeds)
    print(text)
    if args.tables:
        Path(args.tables).parent.mkdir(parents=True, exist_ok=True)
        Path(args.tables).write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
