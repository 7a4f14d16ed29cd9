"""``epistemica view FILE``: a trial's replay as one self-contained HTML page.

:func:`trial_page` replays a trace (:mod:`epistemica.sim.study.trace`) with the panels of the
animation (:mod:`epistemica.sim.study.figures`): the map with sensing radii, estimates and
events, each robot's belief, the configuration-set sizes (own and one robot's model of each
teammate's) and the events; a slider scrubs, a button plays and pauses.

``view`` writes the replay page of one trial (:func:`trial_page`)
from a trace file (JSON, or the compressed bytes of :func:`epistemica.sim.study.trace.encode`),
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

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.spec import MAX_SOURCE_BYTES, read_source
from epistemica.html_view import page, write_page
from epistemica.input_files import read_input
from epistemica.mission import parse_mission
from epistemica.output_files import check_output
from epistemica.sim.engine.simulate import simulate
from epistemica.sim.study.palette import ROBOT_COLOURS, focus_robot
from epistemica.sim.study.trace import FORMAT, READABLE, decode, trial_trace

__all__ = ["read_trace", "run_view", "trial_page"]

_FPS = 6

_SQLITE = b"SQLite format 3\x00"
_ZLIB = b"\x78"  # the first byte of every zlib stream epistemica writes


def read_trace(path: str, seed: int | None = None, level: str | None = None) -> tuple[dict, str]:
    """The trace named by ``path`` (and, for results and mission files, ``seed`` and
    ``level``) and a mission name for the title."""
    # Every branch reads boundedly: the kind is told from the first block, a JSON trace
    # and a mission file are read as text (size limit, binary check), a compressed trace
    # up to the size limit and inflated up to its own (sim.trace.decode).
    head = _read_bytes(path, len(_SQLITE))
    if head.startswith(_SQLITE):
        return _stored_trace(path, seed, level)
    if head[:1] == _ZLIB:
        return decode(_read_bytes(path, MAX_SOURCE_BYTES, whole=True)), ""
    text = read_source(path, "trace or mission file")
    if text.lstrip().startswith("{"):
        try:
            trace = json.loads(text)
        except (ValueError, RecursionError) as exc:  # RecursionError: nested too deeply
            raise InvalidArgumentError(f"{path}: not JSON ({exc})", hint="a trace file") from None
        return trace, ""
    _, text = read_input(path, "view", ("mission",))
    return _simulated_trace(parse_mission(text, path), seed, level)


def _read_bytes(path: str, limit: int, whole: bool = False) -> bytes:
    """The first ``limit`` bytes of the file (``whole``: refuse a longer file)."""
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)
    except OSError as exc:
        raise InvalidArgumentError(f"cannot read {path}: {exc.strerror}", hint="a path") from None
    if whole and len(data) > limit:
        raise InvalidArgumentError(
            f"{path} is larger than the limit of {limit:,} bytes", hint="a trace file"
        )
    return data[:limit]


def _simulated_trace(mission, seed: int | None, level: str | None) -> tuple[dict, str]:
    seed = mission.study.seed if seed is None else seed
    level = mission.study.levels[-1] if level is None else level
    scenario = mission.scenario(seed)
    trial = simulate(
        scenario, level, seed=seed, policies=mission.policies(seed), parameters=mission.parameters
    )
    return trial_trace(scenario, trial), mission.name


def _stored_trace(path: str, seed: int | None, level: str | None) -> tuple[dict, str]:
    try:
        row = _stored_row(path, seed, level)
    except sqlite3.DatabaseError as exc:
        raise InvalidArgumentError(
            f"{path} is not a readable results file ({exc})", hint="a file written by sweep"
        ) from None
    if row is None:
        raise InvalidArgumentError(
            f"{path} has no stored trace for seed {seed} and level {level}",
            hint="choose a stored trial with --trial SEED and --level LEVEL",
        )
    return decode(row[0]), row[1]


def _stored_row(path: str, seed: int | None, level: str | None):
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
        return db.execute(query + " ORDER BY seed, reasoning LIMIT 1", args).fetchone()


def run_view(args: argparse.Namespace) -> int:
    """Run ``epistemica view``; return the exit status."""
    out = Path(args.out) if args.out else Path(Path(args.file).stem + ".html")
    check_output(out, [args.file], args.force, "-o")
    html = trial_page(*read_trace(args.file, args.trial, args.level))
    write_page(out, html)
    print(f"wrote {out} ({len(html.encode()) / 1024:.0f} kB): open it in a browser")
    return 0  # EXIT_OK; not imported, as epistemica.cli dispatches to this module


def trial_page(trace: dict[str, Any], mission: str = "") -> str:
    """The replay page of a trial's trace (``epistemica-trace`` v1) as HTML text."""
    if not isinstance(trace, dict) or trace.get("format") != FORMAT:
        raise InvalidArgumentError(
            "not an epistemica trace", hint="traces are written by epistemica.sim.study.trace"
        )
    if trace.get("kind") == "collaborative":
        raise InvalidArgumentError(
            "a collaborative trial's trace has no beliefs or configuration sets to replay",
            hint="read it with epistemica.sim.study.store.read_trace; "
            "the page replays other missions",
        )
    _check_fields(trace)
    levels = ", ".join(map(str, dict.fromkeys(trace["policies"])))
    outcome = "success" if trace["success"] else "failure"
    head = f"{mission}: " if mission else ""
    title = f"{head}{len(trace['robots'])} robots, {levels}, seed {trace['seed']} ({outcome})"
    try:
        focus = focus_robot(trace)
    except (KeyError, TypeError, ValueError, IndexError) as exc:  # a hand-made trace
        raise InvalidArgumentError(
            f"the trace is incomplete ({type(exc).__name__}: {exc})",
            hint="traces are written by epistemica.sim.study.trace",
        ) from None
    data = {"trace": trace, "colours": list(ROBOT_COLOURS), "focus": focus, "fps": _FPS}
    return page(title, "trial_view.js", data)


#: The fields the page's title and focus are read from, with their JSON types.
_FIELDS = {"robots": list, "goals": list, "policies": list, "poses": list, "seed": int,
           "success": bool, "steps": int}  # fmt: skip


def _check_fields(trace: dict[str, Any]) -> None:
    """Refuse a trace of another version or without the fields the page reads."""
    if trace.get("version") not in READABLE:
        raise InvalidArgumentError(
            f"trace version {trace.get('version')!r:.20}; this epistemica reads "
            + ", ".join(map(str, READABLE)),
            hint="re-run the trial with this version",
        )
    for key, kind in _FIELDS.items():
        if not isinstance(trace.get(key), kind):
            raise InvalidArgumentError(
                f"the trace's {key!r} is {trace.get(key)!r:.40}, not a JSON {kind.__name__}",
                hint="traces are written by epistemica.sim.study.trace",
            )
