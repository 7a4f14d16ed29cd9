"""Every benchmark instance of a plank checkout through ``epistemica plan`` (issue 38).

plank (https://github.com/a-burigana/plank) ships EPDDL domains under
``benchmarks/domains/NAME/*.epddl``, their problems under ``instances/`` and action-type
libraries under ``benchmarks/libraries/``. Each problem is planned in a fresh process with
the libraries its domain declares (``(:action-type-libraries ...)``; a domain whose line
is commented out, Grapevine's, is given every library), a time limit and an address-space
limit, and the script prints one row per instance: the exit status (0 a plan, 1 no plan
exists, 2 a located error or a refused budget, 124 the time limit), the wall time and the
first line of the output. The files are read as shipped; nothing is copied.

With ``--only TEXT`` only the instances whose path contains TEXT are run; with
``--max-depth N`` the search stops at depth N and each row also gives the search's counts
(expanded, generated, distinct states) and its CPU seconds, the median of ``--repeats``
runs: how the cost of a search that does not finish grows with depth.

Usage: ``python benchmarks/plank_suite.py PLANK_CHECKOUT [--seconds 40] [--memory-gib 3]
[--only TEXT] [--max-depth N] [--repeats 1]``
"""

from __future__ import annotations

import argparse
import json
import re
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

_LIBRARIES = re.compile(r"^\s*\(:action-type-libraries\s+([^)]*)\)", re.MULTILINE)


def libraries(domain: Path, folder: Path) -> list[Path]:
    """The libraries a domain declares; every library when it declares none."""
    found = _LIBRARIES.search(domain.read_text(encoding="utf-8"))
    if found is None:
        return sorted(folder.glob("*.epddl"))
    return [folder / f"{name}.epddl" for name in found.group(1).split()]


def run(
    domain: Path,
    problem: Path,
    libs: list[Path],
    seconds: float,
    gib: float,
    depth: int | None = None,
) -> tuple:
    """(exit status, wall seconds, CPU seconds, first line) of one ``epistemica plan``;
    with ``depth``, the first line is the search's counts from its JSON output."""
    argv = [sys.executable, "-m", "epistemica", "plan", str(domain), str(problem)]
    for lib in libs:
        argv += ["-l", str(lib)]
    if depth is not None:
        argv += ["--max-depth", str(depth), "--json"]
    limit = int(gib * 2**30)

    def cap() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    try:
        done = subprocess.run(
            argv, capture_output=True, text=True, timeout=seconds, preexec_fn=cap, check=False
        )
        status, text = done.returncode, (done.stdout or done.stderr).strip()
    except subprocess.TimeoutExpired:
        status, text = 124, f"no answer within {seconds:g} s"
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    if depth is not None and status in (0, 1) and text.startswith("{"):
        found = json.loads(text)
        text = ", ".join(f"{k} {found[k]}" for k in ("length", "expanded", "generated", "distinct"))
    first = text.splitlines()[0] if text else ""
    return status, wall, cpu, first[:110]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plank", type=Path, help="a plank checkout (its benchmarks/ folder)")
    parser.add_argument("--seconds", type=float, default=40.0)
    parser.add_argument("--memory-gib", type=float, default=3.0)
    parser.add_argument("--only", default="", help="instances whose path contains this")
    parser.add_argument("--max-depth", type=int, default=None)
    parser.add_argument("--repeats", type=int, default=1, help="runs per instance (median)")
    args = parser.parse_args(argv)
    root = args.plank / "benchmarks"
    print("| instance | exit | wall s | CPU s | first line |")
    print("|---|---:|---:|---:|---|")
    for domain in sorted(root.glob("domains/*/*.epddl")):
        libs = libraries(domain, root / "libraries")
        for problem in sorted((domain.parent / "instances").rglob("*.epddl")):
            name = problem.relative_to(root / "domains")
            if args.only not in str(name):
                continue
            runs = [
                run(domain, problem, libs, args.seconds, args.memory_gib, args.max_depth)
                for _ in range(args.repeats)
            ]
            status, first = runs[0][0], runs[0][3]
            wall = statistics.median(r[1] for r in runs)
            cpu = statistics.median(r[2] for r in runs)
            print(f"| {name} | {status} | {wall:.1f} | {cpu:.1f} | {first} |", flush=True)


if __name__ == "__main__":
    main()
