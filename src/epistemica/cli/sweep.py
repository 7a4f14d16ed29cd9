"""``epistemica sweep`` and ``epistemica report``: Monte Carlo studies of the simulator.

``sweep`` runs every (mission, robots, goals, level, seed) trial of a grid, or a mission
file's study at each team size of ``--robots`` (files whose robots are ``r1..rN``), on local
processes or a Dask cluster, into an SQLite file (docs/formats.md); ``--resume`` runs only
the trials the file does not hold. :func:`store_trials` is the storing path ``run`` shares.
``report`` reads the file (read-only), prints the success table with 95 % Wilson intervals
and writes the figure.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import dataclass
from functools import partial

from epistemica.cli.exit import EXIT_INTERRUPTED
from epistemica.cli.options import scenario_options
from epistemica.del_.errors import InvalidArgumentError
from epistemica.output_files import check_output, write_output
from epistemica.results import load, write_table
from epistemica.run import team_trials
from epistemica.sim.study.report import format_table, plot_results, study_order, summarise
from epistemica.sim.study.store import ResultStore, read_rows
from epistemica.sim.study.sweep import plan_sweep, run_sweep

__all__ = ["Stored", "run_report", "run_sweep_command", "store_trials"]


def run_sweep_command(args: argparse.Namespace) -> int:

    files = [m for m in args.mission if m.endswith(".epi") or os.path.exists(m)]
    if files:
        specs = _mission_file_trials(files, args)
    else:
        specs = plan_sweep(
            args.mission,
            args.robots or [2],
            args.goals,
            args.reasoning or ["zero", "convention", "third"],
            50 if args.trials is None else args.trials,
            0 if args.seed is None else args.seed,
            scenario_options(args),
        )
    _make_folder(args.out)
    done = store_trials(specs, args.out, args.resume, args)
    if done is None:
        return EXIT_INTERRUPTED
    print(f"{done.summary()} ({sum(r['success'] for r in done.rows)} successes)")
    return 0


def _make_folder(out: str) -> None:
    """Create the results file's folder (``--out runs/x.sqlite`` in a fresh folder), as
    ``run`` does; a clear error where it cannot be made."""
    folder = os.path.dirname(os.path.abspath(out))
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as exc:
        raise InvalidArgumentError(
            f"--out {out}: cannot create the folder {folder} ({exc.strerror})",
            hint="choose a path in a writable folder",
        ) from None


def _mission_file_trials(files: list[str], args: argparse.Namespace) -> list:
    """``sweep --mission FILE``: the file's study at each team size of ``--robots``."""
    if len(files) != len(args.mission):
        raise InvalidArgumentError(
            "--mission takes either mission files or built-in missions, not both",
            hint="run one sweep per kind, into two --out files",
        )
    given = (["goals"] if args.goals is not None else []) + list(scenario_options(args))
    if given:
        raise InvalidArgumentError(
            f"--{given[0].replace('_', '-')} applies to the built-in missions",
            hint="a mission file sets its goals, sensing and steps itself",
        )
    specs = []
    for path in files:
        specs.extend(team_trials(path, args.robots, args.reasoning, args.trials, args.seed))
    return specs


@dataclass
class Stored:
    """What :func:`store_trials` did: trials run, the rows of the study, the time taken."""

    out: str
    ran: int
    rows: list[dict]
    missing: int
    seconds: float

    def summary(self) -> str:
        before = len(self.rows) - self.ran
        elsewhere = f", {self.missing} still running in another sweep" if self.missing else ""
        return (
            f"{self.ran} trials run, {before} already stored, {len(self.rows)} of this study "
            f"in {self.out}{elsewhere} in {self.seconds:.1f} s"
        )


def store_trials(specs, out, resume: bool, args: argparse.Namespace) -> Stored | None:
    """Run the trials of ``specs`` that ``out`` lacks (``sweep`` and ``run``): locally or
    on ``args.scheduler``, with traces unless ``args.no_traces``. None if interrupted
    (Ctrl-C), after saying how many trials are stored."""
    started = time.perf_counter()
    ids = {s.id for s in specs}
    folder = os.path.dirname(os.path.abspath(out))
    try:  # a missing folder is created, rather than called "not a results file"
        os.makedirs(folder, exist_ok=True)
    except OSError as exc:
        raise InvalidArgumentError(
            f"--out {out}: cannot create the folder {folder}: {exc.strerror or exc}",
            hint="choose a path in a writable folder",
        ) from None
    with ResultStore(out, resume=resume) as store:
        done = store.done_ids()
        if getattr(args, "resume", False) and done and not done & ids:
            raise InvalidArgumentError(
                f"--resume: {out} holds {len(done):,} trials, none of them this study's "
                "(another mission, grid or seed range)",
                hint="resume with the command that started the file, or choose another --out",
            )
        bar = _progress(len(ids - done))
        try:
            ran, _ = run_sweep(
                specs,
                store,
                workers=args.workers,
                scheduler=args.scheduler,
                progress=lambda row: bar.update(1) if bar else None,
                traces=not args.no_traces,
            )
        except KeyboardInterrupt:
            stored = len(store.done_ids() & ids)
            print(
                f"\ninterrupted: {stored} of {len(ids)} trials stored in {out}; "
                "run the same command with --resume to finish",
                file=sys.stderr,
            )
            return None
        finally:
            if bar:
                bar.close()
        rows = [r for r in store.rows() if r["id"] in ids]
    return Stored(str(out), ran, rows, len(ids) - len(rows), time.perf_counter() - started)


def _progress(total: int):
    if not sys.stdout.isatty() or total == 0:
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=total, unit="trial", smoothing=0.1)


def _write_data(results: str, path: str) -> None:
    """The trials of ``results`` as CSV or Parquet at ``path`` (checked as every output
    is: :mod:`epistemica.output_files`)."""
    frame = load(results)
    write_output(path, partial(write_table, frame))
    print(f"trials: {path}")


def run_report(args: argparse.Namespace) -> int:

    asked = [(getattr(args, fmt, None), fmt) for fmt in ("png", "pdf", "svg")]
    paths = [(path, fmt) for path, fmt in asked if path]
    paths = paths or [(os.path.splitext(args.results)[0] + ".png", "png")]
    if not args.no_png:  # before reading: never over the results file, nor unasked
        for path, fmt in paths:
            check_output(path, [args.results], args.force, f"--{fmt}")
    for flag in ("csv", "parquet"):
        if getattr(args, flag, None):
            check_output(getattr(args, flag), [args.results], args.force, f"--{flag}")
    cells = summarise(read_rows(args.results))
    # Within a mission and team, the levels in study order (zero, convention, first, ...),
    # as in the figure.
    rank = {name: i for i, name in enumerate(study_order(c.reasoning for c in cells))}
    cells.sort(key=lambda c: (c.mission, c.robots, c.goals, rank[c.reasoning]))
    print(format_table(cells, markdown=args.markdown))
    for path in (getattr(args, "csv", None), getattr(args, "parquet", None)):
        if path:
            _write_data(args.results, path)
    if not args.no_png and cells:
        for path, fmt in paths:
            write_output(path, partial(plot_results, cells, fmt=fmt))
            print(f"figure: {path}")
    return 0
