"""How fast a sweep stops: Ctrl-C (SIGINT to its process group, as a terminal sends it) and
``kill -9`` of the driving process, on a sweep with two local workers busy.

Each repeat starts ``epistemica sweep`` (5-robot allocation at third order, slow enough
that trials are running), waits until 3 rows are stored, interrupts it, and measures: the
seconds until the command returns (SIGINT), or until its workers are gone (kill -9), and
whether every stored row survives (a resumed sweep then runs exactly the missing trials).

    python benchmarks/interruptions.py --repeats 5
"""

from __future__ import annotations

import argparse
import os
import signal
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def _stored(out: Path) -> int:
    try:
        db = sqlite3.connect(f"file:{out}?mode=ro", uri=True)
        return db.execute("SELECT COUNT(*) FROM trials").fetchone()[0]
    except sqlite3.Error:
        return 0


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


def one(out: Path, how: str) -> tuple[float, int]:
    args = [sys.executable, "-m", "epistemica", "sweep", "--mission", "allocation",
            "--robots", "5", "--reasoning", "rules-third", "--trials", "200", "--workers", "2",
            "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)  # fmt: skip
    while _stored(out) < 3:
        time.sleep(0.1)
    found = subprocess.run(["pgrep", "-P", str(proc.pid)], capture_output=True, text=True)
    workers = [int(p) for p in found.stdout.split()]
    started = time.monotonic()
    if how == "sigint":
        os.killpg(proc.pid, signal.SIGINT)
        proc.wait()
    else:
        proc.kill()
        proc.wait()
        while any(_alive(w) for w in workers):
            time.sleep(0.02)
    return time.monotonic() - started, _stored(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for how in ("sigint", "kill9"):
            seconds = []
            for k in range(args.repeats):
                took, _ = one(Path(tmp) / f"{how}{k}.sqlite", how)
                seconds.append(took)
            what = "command returns" if how == "sigint" else "workers gone"
            print(f"{how}: {what} after median {statistics.median(seconds):.2f} s "
                  f"(max {max(seconds):.2f} s) over {args.repeats} runs")  # fmt: skip


if __name__ == "__main__":
    main()
