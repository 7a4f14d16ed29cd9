"""What storing each trial's per-step trace costs a sweep: time and bytes (issue 20).

Runs the same sweep (in this process, one worker, so that the comparison is not blurred by
process start-up) with and without traces, ``--repeats`` times each in alternation, into
fresh results files; prints the median seconds of each, the overhead, and the size of the
stored traces (compressed JSON, :mod:`epistemica.sim.study.trace`) per trial and per 100 steps,
by team size.

    python benchmarks/trace_storage.py --repeats 5
"""

from __future__ import annotations

import argparse
import sqlite3
import statistics
import tempfile
import time
from pathlib import Path

from epistemica.sim.study.store import ResultStore
from epistemica.sim.study.sweep import plan_sweep, run_sweep


def timed_sweep(specs, folder: Path, name: str, traces: bool) -> float:
    path = folder / f"{name}.sqlite"
    started = time.perf_counter()
    with ResultStore(path) as store:
        run_sweep(specs, store, workers=1, traces=traces)
    return time.perf_counter() - started


def trace_sizes(path: Path) -> list[tuple[int, int, int]]:
    """(robots, steps, bytes of the stored trace) per trial."""
    db = sqlite3.connect(path)
    return db.execute("SELECT robots, steps, length(trace) FROM trials").fetchall()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--trials", type=int, default=5)
    args = parser.parse_args()
    specs = plan_sweep(
        ["rendezvous", "allocation"],
        [3, 5],
        None,
        ["zero", "convention", "rules-third"],
        args.trials,
    )
    times: dict[bool, list[float]] = {True: [], False: []}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        timed_sweep(specs[:4], folder, "warm", True)  # imports, caches
        for k in range(args.repeats):
            for traces in (False, True) if k % 2 == 0 else (True, False):
                times[traces].append(timed_sweep(specs, folder, f"{k}-{traces}", traces))
        sizes = trace_sizes(folder / "0-True.sqlite")
        with_file = (folder / "0-True.sqlite").stat().st_size
        without_file = (folder / "0-False.sqlite").stat().st_size
    plain, traced = statistics.median(times[False]), statistics.median(times[True])
    print(f"{len(specs)} trials (rendezvous and allocation, 3 and 5 robots, three levels), "
          f"{args.repeats} repeats")  # fmt: skip
    print(f"median sweep time: {plain:.2f} s without traces, {traced:.2f} s with "
          f"(+{100 * (traced / plain - 1):.1f} %)")  # fmt: skip
    print(f"results file: {without_file / 1024:.0f} kB without, {with_file / 1024:.0f} kB with")
    print("robots  trials  mean steps  trace kB/trial  kB per 100 steps (median, max)")
    for n in sorted({r for r, _, _ in sizes}):
        rows = [(s, b) for r, s, b in sizes if r == n]
        per100 = [100 * b / s / 1024 for s, b in rows if s]
        print(f"{n:6d}  {len(rows):6d}  {statistics.mean(s for s, _ in rows):10.1f}  "
              f"{statistics.mean(b for _, b in rows) / 1024:14.2f}  "
              f"{statistics.median(per100):.2f}, {max(per100):.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
