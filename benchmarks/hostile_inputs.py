"""Benchmark: every reader refuses hostile input within 2 s, with exit status 2 (issue 38).

Each case runs the installed ``epistemica`` command as a fresh process (start-up included)
``--repeats`` times; the median and the largest wall time and the exit statuses are
reported. The cases: ``/dev/zero`` and ``/dev/urandom`` given to each reader (spec,
mission, SMCDEL, EPDDL, policy, results file, view), a 1 GiB zlib bomb as a trace file and
as a trace stored in a results file, and a mission file of a million ``check`` lines.

Usage: ``python benchmarks/hostile_inputs.py [--repeats 5]``; prints a markdown table.
"""

from __future__ import annotations

import argparse
import sqlite3
import statistics
import subprocess
import tempfile
import time
import zlib
from pathlib import Path

from cli_startup import command_line  # a script beside this one

ROOT = Path(__file__).resolve().parents[1]
TARGET = 2.0


def _bomb() -> bytes:
    deflater = zlib.compressobj(9)
    chunk = b" " * (1 << 24)
    return b"".join([*(deflater.compress(chunk) for _ in range(64)), deflater.flush()])


def _cases(folder: Path) -> dict[str, list[str]]:
    for device in ("zero", "urandom"):
        for suffix in ("smcdel", "epddl", "json"):
            (folder / f"{device}.{suffix}").symlink_to(f"/dev/{device}")
    bomb = folder / "bomb.z"
    bomb.write_bytes(_bomb())
    db = folder / "bomb.sqlite"
    with sqlite3.connect(db) as connection:
        connection.execute("CREATE TABLE trials (id, seed, reasoning, mission, trace BLOB)")
        connection.execute("INSERT INTO trials VALUES ('a', 0, 'zero', 'm', ?)", (_bomb(),))
    mission = folder / "big.epi"
    mission.write_text(
        (ROOT / "specs" / "rendezvous.epi").read_text() + 'check "x": K[r1] true\n' * 1_000_000
    )
    implicit = str(ROOT / "specs" / "planning" / "two_robots_implicit.epi")
    page = str(folder / "page.html")
    cases = {}
    for device in ("zero", "urandom"):
        path = f"/dev/{device}"
        cases[f"check {path}"] = ["check", path]
        cases[f"run {path}"] = ["run", path]
        cases[f"view {path}"] = ["view", path, "-o", page]
        cases[f"report {path}"] = ["report", path, "--no-png"]
        cases[f"check {device}.smcdel"] = ["check", str(folder / f"{device}.smcdel")]
        epddl = str(folder / f"{device}.epddl")
        cases[f"plan {device}.epddl"] = ["plan", epddl, epddl]
        policy = str(folder / f"{device}.json")
        cases[f"plan --verify {device}.json"] = [
            "plan", implicit, "--implicit", "--policy", "--verify", policy,
        ]  # fmt: skip
    cases["view 1 GiB zlib bomb"] = ["view", str(bomb), "-o", page]
    cases["view bomb in a results file"] = ["view", str(db), "-o", page]
    cases["check 24 MB mission"] = ["check", str(mission)]
    return cases


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    command = command_line()
    print("| case | exit | median (s) | max (s) | within 2 s |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name, argv in _cases(Path(folder)).items():
            times, codes = [], set()
            for _ in range(args.repeats):
                start = time.perf_counter()
                done = subprocess.run([*command, *argv], capture_output=True, check=False)
                times.append(time.perf_counter() - start)
                codes.add(done.returncode)
            ok = max(times) <= TARGET and codes == {2}
            print(
                f"| `{name}` | {','.join(map(str, sorted(codes)))} | "
                f"{statistics.median(times):.2f} | {max(times):.2f} | {'yes' if ok else 'NO'} |"
            )


if __name__ == "__main__":
    main()
