"""``epistemica sweep`` and ``epistemica report``: Monte Carlo studies of the simulator.

``sweep`` runs every (mission, robots, goals, level, seed) trial of a grid, on local
processes or a Dask cluster, into an SQLite file; ``--resume`` runs only the trials the
file does not hold. ``report`` prints the success table with 95 % Wilson intervals and
writes the figure.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

from epistemica.cli_options import scenario_options
from epistemica.sim.report import format_table, plot_results, summarise
from epistemica.sim.store import ResultStore, read_rows
from epistemica.sim.sweep import plan_sweep, run_sweep

__all__ = ["run_report", "run_sweep_command"]


def run_sweep_command(args: argparse.Namespace) -> int:

    specs = plan_sweep(
        args.mission,
        args.robots,
        args.goals,
        args.reasoning,
        args.trials,
        args.seed,
        scenario_options(args),
    )
    started = time.perf_counter()
    with ResultStore(args.out, resume=args.resume) as store:
        missing = len(specs) - len(store.done_ids() & {s.id for s in specs})
        bar = _progress(missing)
        try:
            ran, skipped = run_sweep(
                specs,
                store,
                workers=args.workers,
                scheduler=args.scheduler,
                progress=lambda row: bar.update(1) if bar else None,
            )
        except KeyboardInterrupt:
            if bar:
                bar.close()
            stored = len(store.done_ids() & {s.id for s in specs})
            print(
                f"interrupted: {stored} of {len(specs)} trials stored in {args.out}; "
                "run the same command with --resume to finish",
                file=sys.stderr,
            )
            return 130
        if bar:
            bar.close()
        ok = sum(r["success"] for r in store.rows())
        total = len(store.rows())
    print(
        f"{ran} trials run, {skipped} already stored, {total} in {args.out} "
        f"({ok} successes) in {time.perf_counter() - started:.1f} s"
    )
    return 0


def _progress(total: int):
    if not sys.stdout.isatty() or total == 0:
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=total, unit="trial", smoothing=0.1)


def run_report(args: argparse.Namespace) -> int:

    cells = summarise(read_rows(args.results))
    print(format_table(cells, markdown=args.markdown))
    if not args.no_png and cells:
        paths = [p for p in (args.png, getattr(args, "pdf", None), getattr(args, "svg", None)) if p]
        for path in paths or [os.path.splitext(args.results)[0] + ".png"]:
            plot_results(cells, path)
            print(f"figure: {path}")
    return 0
