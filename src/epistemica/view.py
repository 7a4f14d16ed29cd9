"""``epistemica view FILE``: a trial's replay as one self-contained HTML page.

``view`` writes the replay page of one trial (:func:`epistemica.sim.html_view.trial_page`)
from a trace file (JSON, or the compressed bytes of :func:`epistemica.sim.trace.encode`),
from a results file whose rows carry traces (an SQLite ``trials`` table with a ``trace``
column), or from a mission file (the trial is simulated). The page is one self-contained
file: open it in any browser, offline. ``show --html`` is :mod:`epistemica.model_view`.
"""

from __future__ import annotations

import argparse
import json
import sqlite3
from pathlib import Path
from typing import Any

from epistemica.cli_exit import EXIT_OK
from epistemica.cli_run import is_mission_file
from epistemica.del_.errors import InvalidArgumentError
from epistemica.mission import load_mission
from epistemica.sim.html_view import trial_page, write_page
from epistemica.sim.simulate import simulate
from epistemica.sim.trace import decode, trial_trace

__all__ = ["read_trace", "run_view"]

_SQLITE = b"SQLite format 3\x00"


def read_trace(path: str, seed: int | None = None, level: str | None = None) -> tuple[dict, str]:
    """The trace named by ``path`` (and, for results and mission files, ``seed`` and
    ``level``) and a mission name for the title."""
    try:
        head = Path(path).read_bytes()[:16]
    except OSError as exc:
        raise InvalidArgumentError(f"cannot read {path}: {exc.strerror}", hint="a path") from None
    if head == _SQLITE:
        return _stored_trace(path, seed, level)
    if is_mission_file(path):
        mission = load_mission(path)
        seed = mission.study.seed if seed is None else seed
        level = mission.study.levels[-1] if level is None else level
        scenario = mission.scenario(seed)
        trial = simulate(
            scenario,
            level,
            seed=seed,
            policies=mission.policies(seed),
            parameters=mission.parameters,
        )
        return trial_trace(scenario, trial), mission.name
    blob = Path(path).read_bytes()
    if blob.lstrip().startswith(b"{"):
        try:
            trace = json.loads(blob)
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise InvalidArgumentError(f"{path}: not JSON ({exc})", hint="a trace file") from None
        return trace, ""
    return decode(blob), ""


def _stored_trace(path: str, seed: int | None, level: str | None) -> tuple[dict, str]:
    with sqlite3.connect(f"file:{path}?mode=ro", uri=True) as db:
        columns = {row[1] for row in db.execute("PRAGMA table_info(trials)")}
        if "trace" not in columns:
            raise InvalidArgumentError(
                f"{path} stores no traces",
                hint="view the mission file instead (the trial is simulated again), "
                "or a trace file",
            )
        query = "SELECT trace, mission FROM trials WHERE trace IS NOT NULL"
        args: list[Any] = []
        if seed is not None:
            query, args = query + " AND seed = ?", [*args, seed]
        if level is not None:
            query, args = query + " AND reasoning = ?", [*args, level]
        row = db.execute(query + " ORDER BY seed, reasoning LIMIT 1", args).fetchone()
    if row is None:
        raise InvalidArgumentError(
            f"{path} has no stored trace for seed {seed} and level {level}",
            hint="choose a stored trial with --trial SEED and --level LEVEL",
        )
    return decode(row[0]), row[1]


def run_view(args: argparse.Namespace) -> int:
    """Run ``epistemica view``; return the exit status."""
    out = Path(args.out) if args.out else Path(Path(args.file).stem + ".html")
    write_page(out, "")  # a missing folder fails now, before any simulation
    html = trial_page(*read_trace(args.file, args.trial, args.level))
    write_page(out, html)
    print(f"wrote {out} ({len(html.encode()) / 1024:.0f} kB): open it in a browser")
    return EXIT_OK
