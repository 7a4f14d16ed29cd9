"""Sweep results in SQLite (``epistemica-results`` schema 2): one row per trial, with its trace.

Every row is committed as it arrives, so a sweep killed at any moment (Ctrl-C, ``kill
-9``) leaves a valid file holding every finished trial exactly once; the trial id is the
primary key, so a resumed sweep cannot duplicate a row. An existing file is never
overwritten: opening it without ``resume=True`` is an error (unless it holds no trial, as
the file of a sweep that failed before its first trial). Before running a trial a sweep
*claims* it (table ``claims``), so that two sweeps on one file share the work instead of
both running it; the claims of a process that died are taken over.

Reading (:func:`read_rows`, :func:`read_trace`) opens the file read-only and never writes to
it: a foreign, corrupted or empty file is refused with a clear error. docs/formats.md
describes every table and column.

Examples
--------
>>> import tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "r.sqlite")
>>> with ResultStore(path) as store:
...     store.claim("t1")
...     store.add({"id": "t1", "mission": "rendezvous", "robots": 2, "goals": 2,
...                "reasoning": "zero", "seed": 0, "options": "{}", "success": 1,
...                "steps": 12, "completion_step": None, "wall_time": 0.1,
...                "decision_ms": 0.05, "considered": 1.0, "version": "0"})
...     sorted(store.done_ids())
True
['t1']
>>> [row["id"] for row in read_rows(path)], read_format(path)
(['t1'], ('epistemica-results', 2))
"""

from __future__ import annotations

import json
import os
import socket
import sqlite3
import time
import uuid
from pathlib import Path

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.study.trace import check_blob_size, decode

__all__ = [
    "COLUMNS",
    "FORMAT",
    "OUTCOME_COLUMNS",
    "SCHEMA_VERSION",
    "ResultStore",
    "read_format",
    "read_rows",
    "read_trace",
]

FORMAT = "epistemica-results"
#: 1: ``trials`` only (0.1.0); 2: ``meta``, ``claims``, the ``trace`` column.
SCHEMA_VERSION = 2

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
    "trace": "BLOB",
}
# Columns added after the first release: an older file gains them when opened to write.
_ADDED = ("unpruned", "trace")
#: The columns of a row as :func:`read_rows` returns it (the trace is read on demand).
ROW_COLUMNS = tuple(c for c in COLUMNS if c != "trace")
#: The columns that depend only on the trial, not on the machine that ran it.
OUTCOME_COLUMNS = tuple(c for c in ROW_COLUMNS if c not in ("wall_time", "decision_ms"))
_REQUIRED = tuple(c for c in ROW_COLUMNS if "NOT NULL" in COLUMNS[c] or c == "id")
#: A results file of more trials is refused before its rows are read: a row read costs
#: about 1.1 kB of memory (500,000 rows peaked at 568 MB in `report`: performance.md,
#: "Input limits"); a sweep stores one row a trial.
MAX_ROWS = 500_000
#: A longer value in one cell of a row (an id, options, a mission name...) is refused: the
#: values epistemica writes are a few hundred bytes.
MAX_CELL_BYTES = 1 << 16
# Seconds a sweep waits for another to let go of the file when opening it.
_OPEN_TIMEOUT = 30.0
# A claim whose owner cannot be checked (another host) lapses after this many seconds.
CLAIM_LIFETIME = 6 * 3600.0


def _not_results(path: str, why: str) -> InvalidArgumentError:
    return InvalidArgumentError(
        f"{path} is not an epistemica results file ({why})",
        hint="pass a file written by `epistemica sweep` or `epistemica run`, or a new path",
    )


def _owner() -> str:
    """HOST:PID:TOKEN, one per open store (two stores of one process are two owners)."""
    return f"{socket.gethostname()}:{os.getpid()}:{uuid.uuid4().hex[:8]}"


def _alive(owner: str, claimed: float, now: float) -> bool:
    host, pid, _ = ["", "", "", *owner.rsplit(":", 2)][-3:]
    if host != socket.gethostname() or not pid.isdigit():
        return now - claimed < CLAIM_LIFETIME
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, owned by someone else
        return True
    return True


class ResultStore:
    """An SQLite results file, opened to add trials.

    Parameters
    ----------
    path : str or os.PathLike
        The results file.
    resume : bool
        Open an existing file and add to it; without it, an existing file that holds a
        trial is an error.
    """

    def __init__(self, path, *, resume: bool = False) -> None:
        self.path = os.fspath(path)
        self.owner = _owner()
        existed = os.path.exists(self.path)
        if existed and not resume and _holds_trials(self.path):
            raise InvalidArgumentError(
                f"{self.path} already exists",
                hint="add --resume to run only its missing trials, or choose another --out",
            )
        # Switching the journal mode takes the file exclusively and SQLite does not wait
        # for it, so a sweep opening the file while another opens or closes it retries.
        deadline = time.monotonic() + _OPEN_TIMEOUT
        while True:
            self._db = None
            try:
                self._db = sqlite3.connect(self.path, timeout=_OPEN_TIMEOUT, isolation_level=None)
                if existed:
                    _check_schema(self._db, self.path, empty_ok=True)
                self._db.execute("PRAGMA journal_mode=WAL")
                self._db.execute("PRAGMA synchronous=FULL")
                self._create()
                return
            except sqlite3.OperationalError as exc:
                if self._db is not None:
                    self._db.close()
                if "locked" not in str(exc) or time.monotonic() > deadline:
                    raise _not_results(self.path, str(exc)) from None
                time.sleep(0.05)
            except sqlite3.DatabaseError as exc:
                raise _not_results(self.path, str(exc)) from None

    def _create(self) -> None:
        db = self._db
        with _transaction(db):
            columns = ", ".join(f"{name} {kind}" for name, kind in COLUMNS.items())
            db.execute(f"CREATE TABLE IF NOT EXISTS trials ({columns})")
            present = {row[1] for row in db.execute("PRAGMA table_info(trials)")}
            for name in _ADDED:
                if name not in present:
                    db.execute(f"ALTER TABLE trials ADD COLUMN {name} {COLUMNS[name]}")
            db.execute("CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT)")
            db.execute(
                "CREATE TABLE IF NOT EXISTS claims "
                "(id TEXT PRIMARY KEY, owner TEXT NOT NULL, claimed REAL NOT NULL)"
            )
            db.executemany(
                "INSERT OR REPLACE INTO meta VALUES (?, ?)",
                [("format", FORMAT), ("version", str(SCHEMA_VERSION))],
            )

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Give up this process's claims and close the file."""
        try:
            self.release()
            # leave one self-contained file (no -wal/-shm) that readers open read-only;
            # another sweep still writing keeps the log (the switch fails: fine)
            self._db.execute("PRAGMA journal_mode=DELETE")
        except sqlite3.OperationalError:
            pass
        finally:
            self._db.close()

    def done_ids(self) -> set[str]:
        """Ids of the trials already stored."""
        return {row[0] for row in self._db.execute("SELECT id FROM trials")}

    def claim(self, trial_id: str) -> bool:
        """Claim a trial for this process: False if it is stored or another live run has it."""
        now = time.time()
        with _transaction(self._db, immediate=True):
            if self._db.execute("SELECT 1 FROM trials WHERE id = ?", (trial_id,)).fetchone():
                return False
            held = self._db.execute(
                "SELECT owner, claimed FROM claims WHERE id = ?", (trial_id,)
            ).fetchone()
            if held and held[0] != self.owner and _alive(held[0], held[1], now):
                return False
            self._db.execute(
                "INSERT OR REPLACE INTO claims VALUES (?, ?, ?)", (trial_id, self.owner, now)
            )
        return True

    def claimed_elsewhere(self) -> int:
        """How many trials other live runs hold now."""
        now = time.time()
        rows = self._db.execute("SELECT owner, claimed FROM claims WHERE owner != ?", (self.owner,))
        return sum(_alive(owner, at, now) for owner, at in rows)

    def release(self) -> None:
        """Give up this process's claims on trials it has not stored."""
        with _transaction(self._db):
            self._db.execute("DELETE FROM claims WHERE owner = ?", (self.owner,))

    def add(self, row: dict) -> None:
        """Store one trial row and commit it (a repeated id is ignored)."""
        names = ", ".join(COLUMNS)
        marks = ", ".join("?" for _ in COLUMNS)
        with _transaction(self._db):
            self._db.execute(
                f"INSERT OR IGNORE INTO trials ({names}) VALUES ({marks})",
                [row.get(c) for c in COLUMNS],
            )
            self._db.execute("DELETE FROM claims WHERE id = ?", (row["id"],))

    def rows(self) -> list[dict]:
        """Every stored row (without its trace), ordered by id."""
        return _rows(self._db)


class _transaction:
    """BEGIN ... COMMIT on an autocommit connection (ROLLBACK on an exception)."""

    def __init__(self, db: sqlite3.Connection, immediate: bool = False) -> None:
        self.db, self.begin = db, "BEGIN IMMEDIATE" if immediate else "BEGIN"

    def __enter__(self) -> None:
        self.db.execute(self.begin)

    def __exit__(self, kind, *exc) -> None:
        self.db.execute("ROLLBACK" if kind else "COMMIT")


def _holds_trials(path: str) -> bool:
    """Whether an existing file holds a trial (a file that is not a results file: True)."""
    try:
        db = _open_read_only(path)
    except InvalidArgumentError:
        return True
    try:
        tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
        if not tables:
            return False
        if "trials" not in tables:
            return True
        return db.execute("SELECT 1 FROM trials LIMIT 1").fetchone() is not None
    except sqlite3.DatabaseError:
        return True
    finally:
        db.close()


def _open_read_only(path: str) -> sqlite3.Connection:
    if not os.path.isfile(path):
        raise InvalidArgumentError(
            f"{path} does not exist" if not os.path.exists(path) else f"{path} is not a file",
            hint="run `epistemica sweep` or `epistemica run` first",
        )
    uri = Path(os.path.abspath(path)).as_uri()
    # immutable: a read-only directory, where the write-ahead log's index cannot be
    # created; the file is read as it is (a finished run leaves every row in it)
    for mode in ("ro", "ro&immutable=1"):
        db = sqlite3.connect(f"{uri}?mode={mode}", uri=True)
        try:
            db.execute("SELECT name FROM sqlite_master").fetchall()
            return db
        except sqlite3.OperationalError as exc:
            db.close()
            error = exc
        except sqlite3.DatabaseError as exc:
            db.close()
            raise _not_results(path, str(exc)) from None
    raise _not_results(path, str(error))


def _check_schema(db: sqlite3.Connection, path: str, empty_ok: bool = False) -> None:
    tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
    if not tables and empty_ok:
        return
    if "trials" not in tables:
        raise _not_results(path, "no 'trials' table" if tables else "an empty database")
    present = {row[1] for row in db.execute("PRAGMA table_info(trials)")}
    missing = [c for c in _REQUIRED if c not in present]
    if missing:
        raise _not_results(path, f"its 'trials' table lacks {', '.join(missing)}")
    if "meta" in tables:
        meta = _meta(db)
        if meta.get("format") != FORMAT:
            raise _not_results(path, f"format {meta.get('format')!r}")
        if not str(meta.get("version", "")).isdigit() or int(meta["version"]) > SCHEMA_VERSION:
            raise InvalidArgumentError(
                f"{path} has results schema {meta.get('version')!r}; this epistemica reads "
                f"schemas 1 to {SCHEMA_VERSION}",
                hint="read it with the epistemica version that wrote it (its 'version' column)",
            )


def _meta(db: sqlite3.Connection) -> dict:
    """The ``format`` and ``version`` entries of the ``meta`` table, each cut to 64
    characters (a hostile table of many or long entries is not read whole)."""
    query = "SELECT key, substr(value, 1, 64) FROM meta WHERE key IN ('format', 'version') LIMIT 2"
    return dict(db.execute(query).fetchall())


def _rows(db: sqlite3.Connection, path: str | None = None) -> list[dict]:
    """The rows; ``path``: a file given to read, whose size is checked first (a sweep's
    own store is not: its rows are the trials it ran)."""
    present = {row[1] for row in db.execute("PRAGMA table_info(trials)")}
    names = [c for c in ROW_COLUMNS if c in present]
    if path is not None:
        _check_size(db, path, names)
    cursor = db.execute(f"SELECT {', '.join(names)} FROM trials ORDER BY id")
    rows = []
    for values in cursor:
        row = dict.fromkeys(ROW_COLUMNS)
        row.update(zip(names, values, strict=True))
        rows.append(row)
    return rows


def _check_size(db: sqlite3.Connection, path: str, names: list[str]) -> None:
    """Refuse a file of more than :data:`MAX_ROWS` trials or a cell longer than
    :data:`MAX_CELL_BYTES`, by counting in SQLite before any row is read."""
    longest = ", ".join(f"ifnull(length({name}), 0)" for name in names)
    count, cell = db.execute(f"SELECT count(*), max(max(0, {longest})) FROM trials").fetchone()
    if count > MAX_ROWS:
        raise _not_results(path, f"{count:,} trials, more than the limit of {MAX_ROWS:,}")
    if (cell or 0) > MAX_CELL_BYTES:
        raise _not_results(path, f"a value of {cell:,} bytes, over the limit of {MAX_CELL_BYTES:,}")


def _validate(rows: list[dict], path: str) -> None:
    for row in rows:
        for column in _REQUIRED:
            if row[column] is None:
                raise _not_results(path, f"trial {row['id']!r} has no {column}")
        for column in ("robots", "goals", "seed", "success", "steps"):
            if not isinstance(row[column], int):
                raise _not_results(path, f"trial {row['id']!r}: {column} is {row[column]!r}")
        if not isinstance(_json_object(row["options"]), dict):
            shown = repr(row["options"])[:60]
            raise _not_results(path, f"trial {row['id']!r}: options {shown} is not a JSON object")


def _json_object(text):
    """``text`` read as JSON, or None when it is not JSON text."""
    try:
        return json.loads(text) if isinstance(text, str) else None
    except ValueError:
        return None


def read_format(path) -> tuple[str, int]:
    """The file's format tag and schema version (schema 1 files carry no tag)."""
    db = _open_read_only(os.fspath(path))
    try:
        _check_schema(db, os.fspath(path))
        tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
        if "meta" not in tables:
            return FORMAT, 1
        return FORMAT, int(_meta(db)["version"])
    finally:
        db.close()


def read_rows(path) -> list[dict]:
    """The rows of an existing results file, read only (the file is never written)."""
    path = os.fspath(path)
    db = _open_read_only(path)
    try:
        _check_schema(db, path)
        rows = _rows(db, path)
    except sqlite3.DatabaseError as exc:
        raise _not_results(path, str(exc)) from None
    finally:
        db.close()
    _validate(rows, path)
    return rows


def read_trace(path, trial_id: str) -> dict | None:
    """The per-step trace of one trial (:mod:`epistemica.sim.study.trace`); None if not stored."""
    path = os.fspath(path)
    db = _open_read_only(path)
    try:
        _check_schema(db, path)
        present = {row[1] for row in db.execute("PRAGMA table_info(trials)")}
        if "trace" not in present:
            return None
        query = "SELECT length(trace) FROM trials WHERE id = ?"
        found = db.execute(query, (trial_id,)).fetchone()
        if found is not None:  # the blob is fetched only within the size limit
            check_blob_size(found[0], f"{path}: the trace of trial {trial_id!r}")
            found = db.execute("SELECT trace FROM trials WHERE id = ?", (trial_id,)).fetchone()
    except sqlite3.DatabaseError as exc:
        raise _not_results(path, str(exc)) from None
    finally:
        db.close()
    if found is None:
        raise InvalidArgumentError(
            f"{path} holds no trial {trial_id!r}", hint="see its 'id' column"
        )
    return None if found[0] is None else decode(found[0])
