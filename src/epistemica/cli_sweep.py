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

from epistemica.cli_options import add_scenario_options, scenario_options

__all__ = ["add_commands", "parse_counts"]

_EXAMPLES = """\
examples:
  epistemica sweep --mission rendezvous --robots 2..5 --goals 2..5 \\
      --reasoning zero,convention,first,third --trials 50 --out results.sqlite
  epistemica sweep ... --out results.sqlite --resume       # after an interruption
  epistemica sweep ... --scheduler tcp://127.0.0.1:8786    # on a Dask cluster
  epistemica report results.sqlite --markdown --png results.png
"""


def parse_counts(text: str) -> list[int]:
    """``"2,3,5"`` or ``"2..5"`` (or a mix, ``"2..4,8"``) as a list of integers.

    Examples
    --------
    >>> parse_counts("2..4,8")
    [2, 3, 4, 8]
    """
    out: list[int] = []
    for part in text.split(","):
        low, dots, high = part.strip().partition("..")
        try:
            a, b = int(low), int(high) if dots else int(low)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected numbers like 2,3,5 or 2..5, got {text!r}"
            ) from None
        if a < 1 or b < a or b - a > 1000:
            raise argparse.ArgumentTypeError(f"expected an increasing range >= 1, got {part!r}")
        out.extend(range(a, b + 1))
    return out


def _names(text: str) -> list[str]:
    return [t.strip() for t in text.split(",") if t.strip()]


def add_commands(commands) -> None:
    """Register ``sweep`` and ``report`` on an argparse subparsers object."""
    sweep = commands.add_parser(
        "sweep",
        help="run a Monte Carlo grid of simulated trials into an SQLite file",
        description="Run every trial of a grid (paper-protocol scenarios) and store one row "
        "per trial; interrupted sweeps resume with --resume.",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sweep.add_argument(
        "--mission",
        type=_names,
        default=["rendezvous"],
        help="rendezvous, allocation, multitask (comma-separated)",
    )
    sweep.add_argument("--robots", type=parse_counts, default=[2], help="e.g. 2..5 or 2,3,5")
    sweep.add_argument(
        "--goals",
        type=parse_counts,
        default=None,
        help="goal counts (default: as many as robots; multitask 20)",
    )
    sweep.add_argument(
        "--reasoning",
        type=_names,
        default=["zero", "convention", "third"],
        help="levels, comma-separated",
    )
    sweep.add_argument("--trials", type=int, default=50, help="seeds per cell (default 50)")
    sweep.add_argument("--seed", type=int, default=0, help="first seed (default 0)")
    sweep.add_argument("--out", required=True, help="results file (SQLite)")
    sweep.add_argument("--resume", action="store_true", help="add the missing trials to --out")
    sweep.add_argument(
        "--workers", type=int, default=None, help="local processes (default: all cores)"
    )
    sweep.add_argument(
        "--scheduler",
        default=None,
        metavar="tcp://HOST:PORT",
        help="run on this Dask scheduler (needs epistemica[cluster])",
    )
    add_scenario_options(sweep)
    sweep.set_defaults(handler=_sweep)

    report = commands.add_parser(
        "report",
        help="print the success table of a results file and write its figure",
        description="Success rate with 95 %% Wilson intervals and mean steps per cell.",
    )
    report.add_argument("results", help="an SQLite file written by `epistemica sweep`")
    report.add_argument("--markdown", action="store_true", help="a markdown table")
    report.add_argument("--png", default=None, help="figure file (default: RESULTS.png)")
    report.add_argument("--no-png", action="store_true", help="do not write the figure")
    report.set_defaults(handler=_report)


def _sweep(args: argparse.Namespace) -> int:
    from epistemica.sim.store import ResultStore
    from epistemica.sim.sweep import plan_sweep, run_sweep

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


def _report(args: argparse.Namespace) -> int:
    from epistemica.sim.report import format_table, plot_results, summarise
    from epistemica.sim.store import read_rows

    cells = summarise(read_rows(args.results))
    print(format_table(cells, markdown=args.markdown))
    if not args.no_png and cells:
        path = args.png or os.path.splitext(args.results)[0] + ".png"
        plot_results(cells, path)
        print(f"figure: {path}")
    return 0
