"""Benchmark: every reader refuses hostile input within 2 s, with exit status 2 (issue 38).

Each case runs the installed ``epistemica`` command as a fresh process (start-up included)
``--repeats`` times; the median and the largest wall time, the largest peak RSS and the
exit statuses are reported. The cases: ``/dev/zero`` and ``/dev/urandom`` given to each
reader (spec, mission, SMCDEL, EPDDL, policy, results file, view), a 1 GiB zlib bomb as a
trace file and as a trace stored in a results file, a mission file of a million ``check``
lines, and a file one item over each item limit: a spec, an SMCDEL and an EPDDL file of
more than ``MAX_TOKENS`` tokens, a mission of more than ``MAX_MISSION_TOKENS``, an SMCDEL
quantifier expanding beyond ``MAX_EXPANSION``, a results file of a 17 MB stored trace and
one of a 1 MB value, a policy nested 100,000 deep.

Usage: ``python benchmarks/hostile_inputs.py [--repeats 5]``; prints a markdown table.
"""

from __future__ import annotations

import argparse
import os
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
    cases.update(_over_the_item_limits(folder, implicit, page))
    return cases


def _over_the_item_limits(folder: Path, implicit: str, page: str) -> dict[str, list[str]]:
    """One file just over each item limit (MAX_TOKENS and the others of docs/formats.md)."""
    over = 1_000_001 // 2 + 1  # '|q' is two tokens: a million and more
    files = {
        "spec.epi": "agents a\natoms p, q\nlaw p" + "|q" * over + "\n",
        "chain.smcdel": "VARS 1,2\nLAW 1" + "|2" * over + "\nOBS a: 1\n",
        "forall.smcdel": "VARS " + ",".join(map(str, range(1, 22))) + "\nLAW Top\nOBS a: 1\n"
        "VALID? Forall " + ",".join(map(str, range(1, 22))) + " 1\n",
        "mission.epi": (ROOT / "specs" / "rendezvous.epi").read_text()
        + 'check "x": '
        + "~" * 250_001
        + "true\n",
        "policy.json": "[" * 100_000 + "]" * 100_000,
    }
    for name, text in files.items():
        (folder / name).write_text(text)
    domain = str(ROOT / "tests" / "data" / "epddl" / "rooms.epddl")
    problem = (ROOT / "tests" / "data" / "epddl" / "rooms-1.epddl").read_text()
    (folder / "big.epddl").write_text(problem.replace("(at r1 room3)", "(at r1 room3)" * 200_001))
    results = folder / "big_trace.sqlite"
    with sqlite3.connect(results) as connection:
        connection.execute("CREATE TABLE trials (id, seed, reasoning, mission, trace BLOB)")
        blob = os.urandom(17 << 20)
        connection.execute("INSERT INTO trials VALUES ('a', 0, 'zero', 'm', ?)", (blob,))
    cell = folder / "big_cell.sqlite"
    with sqlite3.connect(cell) as connection:
        columns = "id, mission, robots, goals, reasoning, seed, options, success, steps, "
        columns += "completion_step, wall_time, decision_ms, considered, version"
        connection.execute(f"CREATE TABLE trials ({columns})")
        row = ("a", "m" * (1 << 20), 2, 2, "zero", 0, "{}", 1, 9, 9, 0.1, 0.1, 1.0, "0")
        connection.execute(f"INSERT INTO trials VALUES ({', '.join('?' * 14)})", row)
    policy = ["plan", implicit, "--implicit", "--policy", "--verify", str(folder / "policy.json")]
    return {
        "check spec of 1,000,002 tokens": ["check", str(folder / "spec.epi")],
        "check SMCDEL of 1,000,008 tokens": ["check", str(folder / "chain.smcdel")],
        "check SMCDEL Forall over 21 variables": ["check", str(folder / "forall.smcdel")],
        "plan EPDDL problem of 1.2 million tokens": ["plan", domain, str(folder / "big.epddl")],
        "check mission of 250,001 nested ~": ["check", str(folder / "mission.epi")],
        "plan --verify policy nested 100,000 deep": policy,
        "view 17 MB trace in a results file": ["view", str(results), "-o", page],
        "report results file of a 1 MB value": ["report", str(cell), "--no-png"],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    command = command_line()
    print("| case | exit | median (s) | max (s) | peak RSS (MB) | within 2 s |")
    print("|---|---|---|---|---:|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name, argv in _cases(Path(folder)).items():
            times, codes, peak = [], set(), 0
            for _ in range(args.repeats):
                start = time.perf_counter()
                child = subprocess.Popen(
                    [*command, *argv], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
                )
                _, status, usage = os.wait4(child.pid, 0)  # this child's own peak RSS
                times.append(time.perf_counter() - start)
                codes.add(os.waitstatus_to_exitcode(status))
                peak = max(peak, usage.ru_maxrss // 1024)
            ok = max(times) <= TARGET and codes == {2}
            print(
                f"| `{name}` | {','.join(map(str, sorted(codes)))} | "
                f"{statistics.median(times):.2f} | {max(times):.2f} | {peak} | "
                f"{'yes' if ok else 'NO'} |"
            )


if __name__ == "__main__":
    main()
