"""Every table of docs/results.md, regenerated from scratch into one folder.

    python benchmarks/reproduce.py --full --workers 2     # the page's numbers (hours)
    python benchmarks/reproduce.py --quick --out runs/reproduce-quick   # CI: a few seeds

Each study runs its trials through the sweep machinery into ``OUT/results/NAME.sqlite``
(resumable: ``--resume`` goes on with a folder a stopped run left) and writes its tables to
``OUT/NAME.md``; docs/results/ holds the files of the ``--full`` run the page quotes, so
``diff -r docs/results OUT`` shows what changed. ``--only NAME,...`` runs some studies.
Trial seeds are 20000 onwards for the shipped missions and the published protocol (no
parameter was ever chosen on them), the locked split for the generated families
(benchmarks/generated_benchmark.py); ``--quick`` runs the first one or two of each and a
prefix of every list of missions, so its numbers are a smoke test, not results.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import generated_benchmark as gb
import numpy as np
import paper_comparison
from paired_tables import versus_table

from epistemica.mission import load_mission
from epistemica.run import mission_trials, run_study
from epistemica.sim.study.report import wilson_interval
from epistemica.sim.study.store import ResultStore, read_rows
from epistemica.sim.study.sweep import plan_sweep

ROOT = Path(__file__).resolve().parents[1]
SEED = 20_000  # first trial seed of the shipped missions and the published protocol
#: The rules' levels the page's tables were measured with (first/second/third before the
#: level switch of issue 37; the planner's are PLANNING_NESTED and THIRD_ORDER).
GOAL_LEVELS = ("convention", "convention+rules", "rules-first", "rules-third-shared", "rules-third")
COLLABORATIVE = (*gb.COLLABORATIVE_LEVELS, "oracle")
PAPER = ("zero", "paper-first", "paper-higher", "paper-higher-fixed")


class Study(NamedTuple):
    """One file of tables: its trials (quick or full) and how to write them."""

    what: str
    specs: Callable[[bool], list]
    table: Callable[[Path, bool], str]


def _rows(path: Path) -> dict:
    """``{((file, seed), 0): {level: (success, steps)}}``: each trial its own cluster."""
    out: dict = {}
    for row in read_rows(path):
        name = json.loads(row["options"]).get("spec", row["mission"])
        key = ((name, row["seed"]), 0)
        out.setdefault(key, {})[row["reasoning"]] = (int(row["success"]), int(row["steps"]))
    return out


def _files(pattern: str, quick_names: tuple[str, ...], quick: bool) -> list[Path]:
    paths = sorted(ROOT.glob(pattern))
    return [p for p in paths if p.stem in quick_names] if quick else paths


def _mission_specs(paths, levels, quick: bool, trials: int) -> list:
    n = 2 if quick else trials
    return [s for p in paths for s in mission_trials(load_mission(p), levels, n, SEED)]


def _per_file(path: Path, levels, focus: str = "rules-third") -> list[str]:
    """Success % (median steps) per file and level, then ``focus`` paired, pooled."""
    rows = _rows(path)
    names = sorted({k[0][0] for k in rows})
    # a file is reported only with every trial of every level (a run stopped mid-file)
    done = [n for n in names if all(set(r) >= set(levels) for k, r in rows.items() if k[0][0] == n)]
    left = [n for n in names if n not in done]
    rows = {k: r for k, r in rows.items() if k[0][0] in done}
    names = done
    out = ["| mission | " + " | ".join(levels) + " |", "|---|" + "---|" * len(levels)]
    for name in names:
        cells = []
        for level in levels:
            got = [r[level] for k, r in rows.items() if k[0][0] == name and level in r]
            ok = sum(s for s, _ in got)
            low, high = wilson_interval(ok, len(got))
            med = np.median([t for _, t in got]) if got else float("nan")
            cells.append(f"{100 * ok / max(len(got), 1):.0f} [{100 * low:.0f}, "
                         f"{100 * high:.0f}] ({med:.0f})")  # fmt: skip
        out.append(f"| {name} | " + " | ".join(cells) + " |")
    rng = np.random.default_rng(20_261_128)
    note = [f"Not finished (the run stopped): {', '.join(left)}.", ""] if left else []
    return [*out, "", *note, *versus_table(rows, focus, levels, rng)]


def _shipped(pattern, quick_names, levels, trials, what, focus: str = "rules-third") -> Study:
    def specs(quick: bool) -> list:
        return _mission_specs(_files(pattern, quick_names, quick), levels, quick, trials)

    def table(path: Path, quick: bool) -> str:
        n = 2 if quick else trials
        head = f"{what}: `{pattern}`, trial seeds {SEED}–{SEED + n - 1}, every level on each."
        return "\n".join([head, "", *_per_file(path, levels, focus), ""])

    return Study(what, specs, table)


def _generated_specs(quick: bool) -> list:
    split = gb.SPLITS["locked"]
    missions, seeds = (2, 1) if quick else (split.missions, len(split.trial_seeds))
    return gb.interleaved(list(gb.FAMILIES), split, missions, seeds)


def _generated_table(path: Path, quick: bool) -> str:
    split = gb.SPLITS["locked"]
    missions, seeds = (2, 1) if quick else (split.missions, len(split.trial_seeds))
    return gb.tables(path, list(gb.FAMILIES), "locked", missions, seeds)


def _paper_specs(quick: bool) -> list:
    n, robots = (2, [2]) if quick else (50, [2, 3, 4, 5])
    goals = [2] if quick else [2, 3, 4, 5]
    rendezvous = plan_sweep(["rendezvous"], robots, goals, PAPER, n, SEED)
    return rendezvous + plan_sweep(["allocation"], robots, None, PAPER, n, SEED)


def _paper_table(path: Path, quick: bool) -> str:
    text = io.StringIO()
    with contextlib.redirect_stdout(text):
        paper_comparison.main([str(path)])
    n = 2 if quick else 50
    head = f"The published protocol, trial seeds {SEED}–{SEED + n - 1} (`{', '.join(PAPER)}`)."
    return head + "\n\n" + text.getvalue()


#: The planner on the published multitask protocol (results.md §1b, "Multitask").
MULTITASK = ("convention", "rules-third", "third-priormode", "third")


def _multitask_specs(quick: bool) -> list:
    robots, goals, n = ([2], [20], 1) if quick else ([2, 3, 5, 8], [20, 30, 40], 5)
    return plan_sweep(["multitask"], robots, goals, MULTITASK, n, SEED)


def _multitask_table(path: Path, quick: bool) -> str:
    """Median / mean completion per team size and level, then `rules-third` paired: each
    (team, tasks, seed) draws its own layout, so each trial is its own cluster."""
    rows: dict = {}
    for row in read_rows(path):
        key = ((f"{row['robots']}x{row['goals']}", row["seed"]), 0)
        rows.setdefault(key, {})[row["reasoning"]] = (int(row["success"]), int(row["steps"]))
    teams = sorted({int(k[0][0].split("x")[0]) for k in rows})
    out = ["| robots | " + " | ".join(f"`{lv}`" for lv in MULTITASK) + " |",
           "|---|" + "---|" * len(MULTITASK)]  # fmt: skip
    for n in teams:
        got = [r for k, r in rows.items() if int(k[0][0].split("x")[0]) == n]
        cells = []
        for level in MULTITASK:
            done = [r[level] for r in got if level in r]
            steps = [t for _, t in done]
            ok = sum(s for s, _ in done)
            cells.append(f"{np.median(steps):.0f} / {np.mean(steps):.1f} ({ok}/{len(done)})")
        out.append(f"| {n} | " + " | ".join(cells) + " |")
    n = 1 if quick else 5
    head = (
        f"The planner on the published multitask protocol, trial seeds {SEED}–{SEED + n - 1}"
        " per (team, tasks) cell. Cells: median / mean completion step (successes)."
    )
    rng = np.random.default_rng(20_261_128)
    return "\n".join([head, "", *out, "", *versus_table(rows, "rules-third", MULTITASK, rng), ""])


#: The planning controller (issue 37) beside the rules' `rules-third` (results.md §1b).
PLANNING_NESTED = ("rules-third", "third", "second", "third-shared")
#: The family where third order decides by construction (results.md §1b), paired on third.
THIRD_ORDER = ("third", "second", "rules-third", "convention")

STUDIES = {
    "generated": Study("generated families, locked split", _generated_specs, _generated_table),
    "collaborative": _shipped(
        "specs/collaborative/tasks_*.epi", ("tasks_3",), COLLABORATIVE, 100,
        "Shipped collaborative missions", focus="rules",
    ),
    "nested": _shipped(
        "specs/nested/*.epi", ("private_goal_3",), GOAL_LEVELS, 100, "Shipped nested missions"
    ),
    "stress": _shipped(
        "specs/stress/*_[235].epi", ("rendezvous_hardest_3",), GOAL_LEVELS, 50,
        "Stress suite at 2, 3 and 5 robots",
    ),
    "paper": Study("published protocol", _paper_specs, _paper_table),
    "planning-nested": _shipped(
        "specs/nested/*.epi", ("private_goal_3",), PLANNING_NESTED, 20,
        "The planning levels beside `rules-third` on the shipped nested missions",
    ),
    "planning-multitask": Study(
        "the planner on the published multitask protocol", _multitask_specs, _multitask_table
    ),
    "third-order": _shipped(
        "specs/third_order/*.epi", ("late_news_3",), THIRD_ORDER, 20,
        "Where third order decides by construction (missions designed on trial seeds "
        "1000–1019)", focus="third",
    ),
}  # fmt: skip


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--quick", action="store_true", help="a few seeds (CI)")
    mode.add_argument("--full", action="store_true", help="every table of the page")
    ap.add_argument("--out", default=None, help="folder (default runs/reproduce-MODE)")
    ap.add_argument("--only", default=",".join(STUDIES), help="comma-separated studies")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--resume", action="store_true", help="go on with an existing folder")
    args = ap.parse_args(argv)
    out = Path(args.out or f"runs/reproduce-{'quick' if args.quick else 'full'}")
    names = [n.strip() for n in args.only.split(",")]
    if any(n not in STUDIES for n in names):
        print(f"error: --only takes {', '.join(STUDIES)}", file=sys.stderr)
        return 2
    if out.exists() and any(out.iterdir()) and not args.resume:
        print(f"error: {out} holds files; add --resume to go on with it, or name a new "
              "folder (nothing is overwritten)", file=sys.stderr)  # fmt: skip
        return 2
    (out / "results").mkdir(parents=True, exist_ok=True)
    for name in names:
        study, started = STUDIES[name], time.perf_counter()
        path = out / "results" / f"{name}.sqlite"
        with ResultStore(str(path), resume=True) as store:
            ran, had = run_study(study.specs(args.quick), store, workers=args.workers)
        (out / f"{name}.md").write_text(study.table(path, args.quick))
        took = time.perf_counter() - started
        print(f"{name}: {study.what}: ran {ran} trials, had {had}, {took:.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
