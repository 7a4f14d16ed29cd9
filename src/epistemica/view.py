"""``epistemica view FILE``: a trial's replay as one self-contained HTML page.

:func:`trial_page` replays a trace (:mod:`epistemica.sim.study.trace`) of any mission kind, one
column per level of the same seed with one shared slider: the map (obstacles, goals or tasks,
axes in metres, sensing radii, events), then the panels the trace's kind names
(:class:`~epistemica.sim.kinds.base.MissionKind` ``panels``). A goal mission's: what each
robot knows (the goals it knows of and how it learned them, the configuration it acts on,
its configuration set), a chosen robot's model of each teammate's knowledge, each robot's
belief (``n/c`` where not computed), the configuration-set sizes. A collaborative
mission's: each task with the robots it needs and when it was done, what each robot steers
to (now, since when, over the trial), the tasks each robot knows of (since when, how), what
a chosen robot knows each teammate knows of. Both: the events; a button plays and pauses.

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
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from epistemica.aif.teammates import TYPE_PRIOR
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.spec import read_source
from epistemica.html_view import page, write_page
from epistemica.input_files import read_input
from epistemica.mission import parse_mission
from epistemica.output_files import check_output
from epistemica.sim.engine.simulate import simulate
from epistemica.sim.kinds.registry import kind_of_trace
from epistemica.sim.study.palette import (
    ROBOT_COLOURS,
    TYPE_MEANINGS,
    fetching_robot,
    focus_reason,
    focus_robot,
)
from epistemica.sim.study.trace import (
    FORMAT,
    MAX_TRACE_BYTES,
    READABLE,
    check_blob_size,
    decode,
    task_learning,
    trial_trace,
    upgraded,
)

__all__ = ["read_trace", "run_view", "trial_page"]

_FPS = 6

_SQLITE = b"SQLite format 3\x00"
_ZLIB = b"\x78"  # the first byte of every zlib stream epistemica writes


def read_trace(path: str, seed: int | None = None, level: str | None = None) -> tuple[dict, str]:
    """The trace named by ``path`` (and, for results and mission files, ``seed`` and
    ``level``) and a mission name for the title."""
    # Every branch reads boundedly: the kind is told from the first block; a JSON trace
    # and a mission file are read as text (binary check) and a compressed trace as bytes,
    # each at most MAX_TRACE_BYTES (the inflated limit: parsing 16 MiB of JSON costs at
    # most about 25 times that), and a compressed trace is inflated up to that limit.
    head = _read_bytes(path, len(_SQLITE))
    if head.startswith(_SQLITE):
        return _stored_trace(path, seed, level)
    if head[:1] == _ZLIB:
        return decode(_read_bytes(path, MAX_TRACE_BYTES, whole=True)), ""
    text = read_source(path, "trace or mission file", MAX_TRACE_BYTES)
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
        # The blob is fetched only once its length is known to be within the limit.
        query = "SELECT rowid, length(trace), mission FROM trials WHERE trace IS NOT NULL"
        args: list[Any] = []
        if seed is not None:
            query, args = query + " AND seed = ?", [*args, seed]
        if level is not None:
            query, args = query + " AND reasoning = ?", [*args, level]
        found = db.execute(query + " ORDER BY seed, reasoning LIMIT 1", args).fetchone()
        if found is None:
            return None
        rowid, size, mission = found
        check_blob_size(size, f"{path}: the stored trace")
        blob = db.execute("SELECT trace FROM trials WHERE rowid = ?", (rowid,)).fetchone()[0]
        return blob, mission


def run_view(args: argparse.Namespace) -> int:
    """Run ``epistemica view``; return the exit status."""
    out = Path(args.out) if args.out else Path(Path(args.file).stem + ".html")
    check_output(out, [args.file], args.force, "-o")
    trace, mission = read_trace(args.file, args.trial, args.level)
    others = []
    for level in args.compare or ():
        if mission == "" and not _holds_trials(args.file):
            raise InvalidArgumentError(
                f"--compare {level}: {args.file} holds one trial",
                hint="compare levels on a mission file or a results file storing traces",
            )
        others.append(read_trace(args.file, trace["seed"], level)[0])
    html = trial_page(trace, mission, others)
    write_page(out, html)
    print(f"wrote {out} ({len(html.encode()) / 1024:.0f} kB): open it in a browser")
    return 0  # EXIT_OK; not imported, as epistemica.cli dispatches to this module


def _holds_trials(path: str) -> bool:
    """Whether ``path`` is a results file (a mission file names its mission)."""
    return _read_bytes(path, len(_SQLITE)) == _SQLITE


def trial_page(trace: dict[str, Any], mission: str = "", others: Sequence[dict] = ()) -> str:
    """The replay page of a trial's trace (``epistemica-trace``) as HTML text; ``others``:
    traces of the same trial at other levels, drawn beside it with one shared slider.

    Examples
    --------
    >>> from epistemica.sim import Scenario, simulate
    >>> from epistemica.sim.study.trace import trial_trace
    >>> s = Scenario.paper("rendezvous", 2, 2, seed=0, max_steps=5)
    >>> a, b = (trial_trace(s, simulate(s, level, seed=0)) for level in ("zero", "first"))
    >>> html = trial_page(a, "demo", [b])
    >>> "demo: 2 robots, seed 0: zero failed within 5 steps; first" in html
    True
    """
    traces = []
    for t in [trace, *others]:
        if not isinstance(t, dict) or t.get("format") != FORMAT:
            raise InvalidArgumentError(
                "not an epistemica trace", hint="traces are written by epistemica.sim.study.trace"
            )
        traces.append(upgraded(t))
    trials = [_trial(t) for t in traces]
    if len({tuple(p["panels"]) for p in trials}) > 1:
        raise InvalidArgumentError(
            "the traces are of different kinds of mission", hint="compare levels of one trial"
        )
    verdicts = "; ".join(f"{p['level']} {_outcome(p['trace'])}" for p in trials)
    head = f"{mission}: " if mission else ""
    title = f"{head}{len(traces[0]['robots'])} robots, seed {traces[0]['seed']}: {verdicts}"
    data = {"trials": trials, "colours": list(ROBOT_COLOURS), "fps": _FPS}
    return page(title, ("trial_parts.js", "trial_panels.js", "trial_view.js"), data)


def _trial(trace: dict[str, Any]) -> dict[str, Any]:
    """A column's data: the trace, its level, its kind's panels, the robot whose model of
    its teammates is shown first and, of a joint trial, how each robot learned each task."""
    kind = kind_of_trace(trace)
    _check_fields(trace, _JOINT_FIELDS if kind.joint else _GOAL_FIELDS)
    if kind.joint:
        _check_shapes(trace)
    column = {"trace": trace, "level": _level(trace), "panels": list(kind.panels)}
    try:
        column["focus"] = fetching_robot(trace) if kind.joint else focus_robot(trace)
        if kind.joint:
            column["learned"] = task_learning(trace)
        else:
            column["focus_why"] = focus_reason(trace)
            column["type_meanings"] = TYPE_MEANINGS
            column["type_prior"] = [round(float(v), 2) for v in TYPE_PRIOR]
    except (KeyError, TypeError, ValueError, IndexError) as exc:  # a hand-made trace
        raise InvalidArgumentError(
            f"the trace is incomplete ({type(exc).__name__}: {exc})",
            hint="traces are written by epistemica.sim.study.trace",
        ) from None
    return column


def _level(trace: dict[str, Any]) -> str:
    return ", ".join(map(str, dict.fromkeys(trace["policies"])))


def _outcome(trace: dict[str, Any]) -> str:
    if trace["success"]:
        return f"succeeded at step {trace['steps']}"
    return f"failed within {trace['steps']} steps"


#: The fields the page's title and focus are read from, with their JSON types.
_FIELDS = {"robots": list, "goals": list, "policies": list, "poses": list, "seed": int,
           "success": bool, "steps": int}  # fmt: skip
_GOAL_FIELDS = {**_FIELDS, "modelled": list, "considered": list}
#: A joint trial's: its task ledger and what each robot steered to.
_JOINT_FIELDS = {**_FIELDS, "goal_positions": list, "needs": list, "tasks_done": list,
                 "steer_to": list, "tasks_known": list, "aware_since": list, "events": list,
                 "sensing_range": (int, float)}  # fmt: skip


def _check_shapes(trace: dict[str, Any]) -> None:
    """Refuse a joint trace whose arrays do not fit its steps, robots and tasks (the page
    would index past them)."""
    steps, n, m = trace["steps"], len(trace["robots"]), len(trace["goals"])
    shapes = {"poses": (steps + 1, n, 3), "goal_positions": (m, 2), "needs": (m,),
              "tasks_done": (m,), "steer_to": (steps, n), "tasks_known": (steps, n, m),
              "aware_since": (n, n, m), "sensors": (n,), "policies": (n,)}  # fmt: skip
    for key, shape in shapes.items():
        try:
            found = np.shape(np.asarray(trace[key], dtype=object if key in _NAMES else float))
        except (TypeError, ValueError):  # ragged, or not numbers
            found = None
        if found != shape:
            raise InvalidArgumentError(
                f"the trace's {key!r} is not an array of shape {shape} ({steps} steps, "
                f"{n} robots, {m} tasks)",
                hint="traces are written by epistemica.sim.study.trace",
            )


_NAMES = ("sensors", "policies")


def _check_fields(trace: dict[str, Any], fields: dict[str, Any]) -> None:
    """Refuse a trace of another version or without the fields the page reads."""
    if trace.get("version") not in READABLE:
        raise InvalidArgumentError(
            f"trace version {trace.get('version')!r:.20}; this epistemica reads "
            + ", ".join(map(str, READABLE)),
            hint="re-run the trial with this version",
        )
    for key, kind in fields.items():
        if not isinstance(trace.get(key), kind) or isinstance(trace.get(key), bool) != (
            kind is bool
        ):
            name = "number" if isinstance(kind, tuple) else kind.__name__
            raise InvalidArgumentError(
                f"the trace's {key!r} is {trace.get(key)!r:.40}, not a JSON {name}",
                hint="traces are written by epistemica.sim.study.trace",
            )
