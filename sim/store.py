"""Sweep results in SQLite: one row per trial, written only by the driving process.

Every row is committed as it arrives, so a sweep killed at any moment (Ctrl-C, ``kill
-9``) leaves a valid file holding every finished trial exactly once; the trial id is the
primary key, so a resumed sweep cannot duplicate a row. An existing file is never
overwritten: opening it without ``resume=True`` is an error.

Examples
--------
>>> import tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "r.sqlite")
>>> with ResultStore(path) as store:
...     store.add({"id": "t1", "mission": "rendezvous", "robots": 2, "goals": 2,
...                "reasoning": "zero", "seed": 0, "options": "{}", "success": 1,
...                "steps": 12, "completion_step": None, "wall_time": 0.1,
...                "decision_ms": 0.05, "considered": 1.0, "version": "0"})
...     sorted(store.done_ids())
['t1']
"""

from __future__ import annotations

import os
import sqlite3

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["COLUMNS", "OUTCOME_COLUMNS", "ResultStore", "read_rows"]

#: Columns of the ``trials`` table, in order, with their SQL types.
COLUMNS = {
    "id": "TEXT PRIMARY KEY",
    "mission": "TEXT NOT NULL",
    "robots": "INTEGER NOT NULL",
    "goals": "INTEGER NOT NULL",
    "reasoning": "TEXT NOT NULL",
    "seed": "INTEGER NOT NULL",
    "options": "TEXT NOT NULL",
    "success": "INTEGER NOT NULL",
    "steps": "INTEGER NOT NULL",
    "completion_step": "INTEGER",
    "wall_time": "REAL NOT NULL",
    "decision_ms": "REAL NOT NULL",
    "considered": "REAL NOT NULL",
    "version": "TEXT NOT NULL",
    "unpruned": "REAL",
}
# Columns added after the first release: an older file gains them when opened.
_ADDED = ("unpruned",)
#: The columns that depend only on the trial, not on the machine that ran it.
OUTCOME_COLUMNS = tuple(c for c in COLUMNS if c not in ("wall_time", "decision_ms"))


class ResultStore:
    """An SQLite file of trial rows.

    Parameters
    ----------
    path : str or os.PathLike
        The results file.
    resume : bool
        Open an existing file and add to it; without it, an existing file is an error.
    """

    def __init__(self, path, *, resume: bool = False) -> None:
        self.path = os.fspath(path)
        if os.path.exists(self.path) and not resume:
            raise InvalidArgumentError(
                f"{self.path} already exists",
                hint="add --resume to run only its missing trials, or choose another --out",
            )
        try:
            self._db = sqlite3.connect(self.path)
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("PRAGMA synchronous=FULL")
            columns = ", ".join(f"{name} {kind}" for name, kind in COLUMNS.items())
            self._db.execute(f"CREATE TABLE IF NOT EXISTS trials ({columns})")
            present = {row[1] for row in self._db.execute("PRAGMA table_info(trials)")}
            for name in _ADDED:
                if name not in present:
                    self._db.execute(f"ALTER TABLE trials ADD COLUMN {name} {COLUMNS[name]}")
            self._db.commit()
        except sqlite3.DatabaseError as exc:
            raise InvalidArgumentError(
                f"{self.path} is not a results file ({exc})",
                hint="pass a file written by `epistemica sweep`, or a new path",
            ) from exc

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Commit and close the file."""
        self._db.commit()
        self._db.close()

    def done_ids(self) -> set[str]:
        """Ids of the trials already stored."""
        return {row[0] for row in self._db.execute("SELECT id FROM trials")}

    def add(self, row: dict) -> None:
        """Store one trial row and commit it (a repeated id is ignored)."""
        names = ", ".join(COLUMNS)
        marks = ", ".join("?" for _ in COLUMNS)
        with self._db:
            self._db.execute(
                f"INSERT OR IGNORE INTO trials ({names}) VALUES ({marks})",
                [row.get(c) for c in COLUMNS],
            )

    def rows(self) -> list[dict]:
        """Every stored row, ordered by id."""
        cursor = self._db.execute(f"SELECT {', '.join(COLUMNS)} FROM trials ORDER BY id")
        return [dict(zip(COLUMNS, values, strict=True)) for values in cursor]


def read_rows(path) -> list[dict]:
    """The rows of an existing results file (read only)."""
    if not os.path.exists(path):
        raise InvalidArgumentError(f"{path} does not exist", hint="run `epistemica sweep` first")
    with ResultStore(path, resume=True) as store:
        return store.rows()
