"""``epistemica view FILE``: a trial's replay as one self-contained HTML page.

:func:`trial_page` replays a trace (:mod:`epistemica.sim.trace`), one column per level of
the same seed with one shared slider: the map (obstacles, open and closed goals, axes in
metres, sensing radii, estimates, events), what each robot knows (the goals it knows of and
how it learned them, the configuration it acts on, its configuration set), the focus
robot's model of each teammate's knowledge, each robot's belief (``n/c`` where not
computed), the configuration-set sizes and the events; a button plays and pauses.

``view`` writes the replay page of one trial (:func:`trial_page`)
from a trace file (JSON, or the compressed bytes of :func:`epistemica.sim.trace.encode`),
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

from epistemica.cli_exit import EXIT_OK
from epistemica.del_.errors import InvalidArgumentError
from epistemica.html_view import check_writable, page, write_page
from epistemica.input_files import file_kind, read_input
from epistemica.mission import parse_mission
from epistemica.sim.palette import ROBOT_COLOURS, focus_robot
from epistemica.sim.simulate import simulate
from epistemica.sim.trace import FORMAT, decode, trial_trace

__all__ = ["read_trace", "run_view", "trial_page"]

_FPS = 6

_SQLITE = b"SQLite format 3\x00"


def read_trace(path: str, seed: int | None = None, level: str | None = None) -> tuple[dict, str]:
    """The trace named by ``path`` (and, for results and mission files, ``seed`` and
    ``level``) and a mission name for the title."""
    try:
        blob = Path(path).read_bytes()
    except OSError as exc:
        raise InvalidArgumentError(f"cannot read {path}: {exc.strerror}", hint="a path") from None
    if blob.startswith(_SQLITE):
        return _stored_trace(path, seed, level)
    if blob.lstrip().startswith(b"{"):
        try:
            trace = json.loads(blob)
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise InvalidArgumentError(f"{path}: not JSON ({exc})", hint="a trace file") from None
        return trace, ""
    try:
        kind = file_kind(blob.decode("utf-8"))[0]
    except UnicodeDecodeError:
        kind = "binary"
    if kind in ("mission", "headless"):
        _, text = read_input(path, "view", ("mission",))
        return _simulated_trace(parse_mission(text, path), seed, level)
    return decode(blob), ""


def _simulated_trace(mission, seed: int | None, level: str | None) -> tuple[dict, str]:
    seed = mission.study.seed if seed is None else seed
    level = mission.study.levels[-1] if level is None else level
    scenario = mission.scenario(seed)
    trial = simulate(
        scenario, level, seed=seed, policies=mission.policies(seed), parameters=mission.parameters
    )
    return trial_trace(scenario, trial), mission.name


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
    check_writable(out)
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
    return EXIT_OK


def _holds_trials(path: str) -> bool:
    """Whether ``path`` is a results file (a mission file names its mission)."""
    return Path(path).read_bytes()[: len(_SQLITE)] == _SQLITE


def trial_page(trace: dict[str, Any], mission: str = "", others: Sequence[dict] = ()) -> str:
    """The replay page of a trial's trace (``epistemica-trace``) as HTML text; ``others``:
    traces of the same trial at other levels, drawn beside it with one shared slider.

    Examples
    --------
    >>> from epistemica.sim import Scenario, simulate
    >>> from epistemica.sim.trace import trial_trace
    >>> s = Scenario.paper("rendezvous", 2, 2, seed=0, max_steps=5)
    >>> a, b = (trial_trace(s, simulate(s, level, seed=0)) for level in ("zero", "first"))
    >>> html = trial_page(a, "demo", [b])
    >>> "demo: 2 robots, seed 0: zero failed within 5 steps; first" in html
    True
    """
    traces = [trace, *others]
    for t in traces:
        if not isinstance(t, dict) or t.get("format") != FORMAT:
            raise InvalidArgumentError(
                "not an epistemica trace", hint="traces are written by epistemica.sim.trace"
            )
        if t.get("kind") == "collaborative":
            raise InvalidArgumentError(
                "a collaborative trial's trace has no beliefs or configuration sets to replay",
                hint="read it with epistemica.sim.store.read_trace; the page replays other "
                "missions",
            )
    trials = [{"trace": t, "level": _level(t), "focus": focus_robot(t)} for t in traces]
    verdicts = "; ".join(f"{p['level']} {_outcome(p['trace'])}" for p in trials)
    head = f"{mission}: " if mission else ""
    title = f"{head}{len(trace['robots'])} robots, seed {trace['seed']}: {verdicts}"
    data = {"trials": trials, "colours": list(ROBOT_COLOURS), "fps": _FPS}
    return page(title, "trial_view.js", data)


def _level(trace: dict[str, Any]) -> str:
    return ", ".join(dict.fromkeys(trace["policies"]))


def _outcome(trace: dict[str, Any]) -> str:
    if trace["success"]:
        return f"succeeded at step {trace['steps']}"
    return f"failed within {trace['steps']} steps"
