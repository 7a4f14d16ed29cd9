"""Results files as data: pandas DataFrames of trials and of steps.

:func:`load` reads a results file (``epistemica sweep`` or ``run``; read only, the file is
never written) into a DataFrame with one row per trial (the columns of the ``trials``
table, docs/formats.md, less the trace); :func:`load_steps` reads the stored traces into
one row per trial, step and robot. Both need pandas: ``pip install "epistemica[data]"``
(the ``data`` extra adds pyarrow too, for ``report --parquet``).

Examples
--------
>>> import contextlib, io, os, tempfile
>>> from epistemica.cli import main
>>> path = os.path.join(tempfile.mkdtemp(), "r.sqlite")
>>> with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
...     code = main(["sweep", "--robots", "2", "--trials", "2", "--reasoning", "zero,first",
...                  "--out", path])
>>> trials = load(path)
>>> code, len(trials), sorted(set(trials["reasoning"]))
(0, 4, ['first', 'zero'])
>>> steps = load_steps(path)  # one row per trial, step and robot
>>> len(steps) == int((trials["steps"] * trials["robots"]).sum())
True
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from typing import Any

from epistemica.del_.errors import EpistemicaError, InvalidArgumentError
from epistemica.sim.study.store import read_rows, read_trace
from epistemica.sim.study.trace import known_goals

__all__ = ["MAX_STEP_ROWS", "STEP_COLUMNS", "load", "load_steps", "write_table"]

#: The columns of :func:`load_steps`, in order.
STEP_COLUMNS = (
    "id", "mission", "reasoning", "seed", "step", "robot", "x", "y", "heading",
    "considered", "unpruned", "goal", "belief", "known_goals",
)  # fmt: skip


def _pandas():
    try:
        import pandas
    except ImportError:
        raise EpistemicaError(
            "results as data need pandas",
            hint='install the data extra: pip install "epistemica[data]"',
        ) from None
    return pandas


def load(path) -> Any:
    """The trials of a results file as a pandas DataFrame, one row per trial, sorted by
    mission, level, team size and seed (``success`` as bool)."""
    pandas = _pandas()
    rows = read_rows(os.fspath(path))
    frame = pandas.DataFrame(rows)
    if frame.empty:
        return frame
    frame["success"] = frame["success"].astype(bool)
    order = ["mission", "reasoning", "robots", "goals", "seed"]
    return frame.sort_values(order, kind="stable").reset_index(drop=True)


#: The most step rows :func:`load_steps` builds unless told otherwise (about 1.5 GB at
#: 0.7 kB a row; a sweep of 100,000 trials of 5 robots over 100 steps holds 50 million).
MAX_STEP_ROWS = 2_000_000


def load_steps(path, ids: Iterable[int] | None = None, max_rows: int | None = MAX_STEP_ROWS) -> Any:
    """Every stored trace of a results file as a pandas DataFrame: one row per trial,
    step and robot (:data:`STEP_COLUMNS`): the pose after the step's decision (``x``,
    ``y``, ``heading``, m and rad), the configuration-set sizes, the goal the robot acted on
    (``goal``, a name; empty when none) with its belief in it, and how many goals it knew
    of (``known_goals``). Values a trace does not hold are missing (NaN).

    ``ids`` keeps only those trials (the ``id`` column of :func:`load`). The rows are
    counted from the trials table before any trace is read: more than ``max_rows`` is
    refused with a hint (``None`` reads everything, however large).
    """
    if max_rows is not None and (
        isinstance(max_rows, bool) or not isinstance(max_rows, int) or max_rows < 1
    ):
        raise InvalidArgumentError(
            f"max_rows must be a positive integer or None, not {max_rows!r}",
            hint="pass the most step rows to build, or None for no limit",
        )
    pandas = _pandas()
    rows = read_rows(os.fspath(path))
    if ids is not None:
        wanted = set(ids)
        rows = [row for row in rows if row["id"] in wanted]
    total = sum(int(row["steps"]) * int(row["robots"]) for row in rows)
    if max_rows is not None and total > max_rows:
        raise InvalidArgumentError(
            f"{os.fspath(path)}: the traces of {len(rows):,} trials hold {total:,} step rows, "
            f"more than max_rows={max_rows:,}",
            hint="choose trials with ids=load(path).query(...)['id'], or pass a larger "
            "max_rows (None for no limit)",
        )
    out: list[tuple] = []
    for row in rows:
        trace = read_trace(os.fspath(path), row["id"])
        if trace is None:
            continue
        out.extend(_step_rows(row, trace))
    return pandas.DataFrame(out, columns=list(STEP_COLUMNS))


def _step_rows(row: dict, trace: dict) -> list[tuple]:
    known = known_goals(trace) if "knows" in trace else None
    robots, goals = trace.get("robots", []), trace.get("goals", [])
    nan = float("nan")
    out = []
    for step in range(int(trace["steps"])):
        pose = trace["poses"][step + 1]
        for i, name in enumerate(robots):
            focal = trace["focal"][step][i][i] if "focal" in trace else -1
            goal = goals[focal] if focal >= 0 else ""
            belief = trace["goal_belief"][step][i][focal] if focal >= 0 else nan
            considered = _at(trace, "considered", step, i)
            unpruned = _at(trace, "unpruned", step, i)
            count = int(known[step, i, i].sum()) if known is not None else len(goals)
            if "tasks_known" in trace:  # a joint trial: the tasks it knew of
                count = int(sum(trace["tasks_known"][step][i]))
            values = (row["id"], row["mission"], row["reasoning"], row["seed"], step, name)
            x, y, heading = (nan if v is None else v for v in pose[i][:3])
            out.append((*values, x, y, heading, considered, unpruned, goal, belief, count))
    return out


def _at(trace: dict, key: str, step: int, i: int) -> float:
    series = trace.get(key)
    if not isinstance(series, list) or step >= len(series):
        return float("nan")
    value = series[step]
    return float(value[i]) if isinstance(value, list) else float("nan")


def write_table(frame, path) -> None:
    """Write a DataFrame as CSV or Parquet, by ``path``'s suffix (``.csv``, ``.parquet``)."""
    path = os.fspath(path)
    try:
        if path.endswith(".parquet"):
            try:
                frame.to_parquet(path, index=False)
            except ImportError:
                raise EpistemicaError(
                    "Parquet needs pyarrow",
                    hint='install the data extra: pip install "epistemica[data]"',
                ) from None
        else:
            frame.to_csv(path, index=False)
    except OSError as exc:
        raise InvalidArgumentError(
            f"cannot write {path}: {exc.strerror}", hint="choose a path in an existing folder"
        ) from None
