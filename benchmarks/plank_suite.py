"""Every benchmark instance of a plank checkout through ``epistemica plan`` (issue 38).

plank (https://github.com/a-burigana/plank) ships EPDDL domains under
``benchmarks/domains/NAME/*.epddl``, their problems under ``instances/`` and action-type
libraries under ``benchmarks/libraries/``. Each problem is planned in a fresh process with
the libraries its domain declares (``(:action-type-libraries ...)``; a domain that
declares none, such as Grapevine whose line is commented out, is given the first library
that defines every action type it uses, as plank rejects two libraries that define one
name), a time limit and an address-space limit. One row per instance: the exit status (0
a plan, 1 no plan exists, 2 a located error or a refused budget, 124 the time limit), the
answer (the plan's length, "no plan" when the search is exhaustive, or the first line of
the output), the wall time and the CPU time. The files are read as shipped.

With ``--plank BIN`` (plank's ``plank`` executable, built from its sources) every plan
found is given to ``plank validate`` in plank's action names and its verdict is a column;
with ``--plank-bfs BIN`` (plank's ``bfs_planner``) plank's own breadth-first search runs on
the same files, within ``--seconds``, and its plan length and run time are a column.

With ``--only TEXT`` only the instances whose path contains TEXT are run; with
``--max-depth N`` the search stops at depth N and the answer also gives the search's counts
(expanded, generated, distinct states); the times are the medians of ``--repeats`` runs.
``--search`` and ``--memory-gib`` pass to ``epistemica plan``.

Usage: ``python benchmarks/plank_suite.py PLANK_CHECKOUT [--seconds 40] [--memory-gib 3]
[--only TEXT] [--max-depth N] [--repeats 1] [--search bfs] [--plank BIN] [--plank-bfs BIN]``
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

from epddl import libraries_for, plank_verdict  # a script beside this one

_PLANK_TIME = re.compile(r"^Runtime: ([0-9]+(?:\.[0-9]+)?)", re.MULTILINE)
_PLANK_STEP = re.compile(r"^\d+\. (\S+)$", re.MULTILINE)


def run(
    domain: Path, problem: Path, libs: list[Path], args: argparse.Namespace
) -> tuple[int, float, float, str, list[str] | None]:
    """(exit status, wall seconds, CPU seconds, answer, plan in plank's names) of one
    ``epistemica plan --json``."""
    argv = [sys.executable, "-m", "epistemica", "plan", str(domain), str(problem), "--json"]
    for lib in libs:
        argv += ["-l", str(lib)]
    argv += ["--search", args.search, "--memory-budget", f"{args.memory_gib:g}"]
    if args.max_depth is not None:
        argv += ["--max-depth", str(args.max_depth)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = limited(argv, args)
    if done is None:
        status, text = 124, f"no answer within {args.seconds:g} s"
    else:
        status, text = done.returncode, (done.stdout or done.stderr).strip()
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    if status in (0, 1) and text.startswith("{"):
        found = json.loads(text)
        return status, wall, cpu, answer(found, args.max_depth is not None), found.get("plank_plan")
    first = text.splitlines()[0] if text else ""
    return status, wall, cpu, first[:110], None


def limited(argv: list[str], args: argparse.Namespace) -> subprocess.CompletedProcess | None:
    """Run ``argv`` within ``--seconds`` and an address space of ``--memory-gib`` GiB and
    512 MiB (room for the interpreter beside the memory budget); None on the time limit."""
    limit = int(args.memory_gib * 2**30) + 2**29

    def cap() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    try:
        return subprocess.run(
            argv, capture_output=True, text=True, timeout=args.seconds, preexec_fn=cap, check=False
        )
    except subprocess.TimeoutExpired:
        return None


def answer(found: dict, counts: bool) -> str:
    """The answer column of one JSON output of ``epistemica plan``."""
    if found["plan"] is not None:
        text = f"plan of {found['length']}"
    else:
        text = "no plan" if found["complete"] else "none within the bound"
    if counts:
        text += ", " + ", ".join(f"{k} {found[k]}" for k in ("expanded", "generated", "distinct"))
    return text


def plank_bfs(bfs: Path, domain: Path, problem: Path, libs: list[Path], args) -> str:
    """plank's ``bfs_planner`` on one instance, within the time and memory limits: its
    plan's length and the run time it reports (wall), or why there is none."""
    argv = [str(bfs), "-d", str(domain), "-p", str(problem)]
    if libs:
        argv += ["-l", *map(str, libs)]
    start = time.perf_counter()
    done = limited(argv, args)
    if done is None:
        return f"none within {args.seconds:g} s"
    wall = time.perf_counter() - start
    reported = _PLANK_TIME.search(done.stdout)
    took = f"{float(reported.group(1)):.3f} s" if reported else f"{wall:.3f} s wall"
    if "Plan found:" in done.stdout:
        return f"{len(_PLANK_STEP.findall(done.stdout))} ({took})"
    if "No plan found." in done.stdout:
        return f"no plan ({took})"
    lines = [ln for ln in done.stdout.splitlines() if ln.strip()]
    return f"exit {done.returncode}: {lines[-1][:60] if lines else ''}"


def row(domain: Path, problem: Path, name: Path, args: argparse.Namespace) -> str:
    """The table row of one instance."""
    libs = libraries_for(domain, sorted((args.plank_root / "benchmarks/libraries").glob("*.epddl")))
    runs = [run(domain, problem, libs, args) for _ in range(args.repeats)]
    status, _, _, text, plank_plan = runs[0]
    wall = statistics.median(r[1] for r in runs)
    cpu = statistics.median(r[2] for r in runs)
    cells = [str(name), str(status), text, f"{wall:.1f}", f"{cpu:.1f}"]
    if args.plank is not None:
        verdict = ""
        if plank_plan is not None:
            verdict = plank_verdict(args.plank, domain, problem, libs, plank_plan, args.seconds)
        cells.append(verdict)
    if args.plank_bfs is not None:
        cells.append(plank_bfs(args.plank_bfs, domain, problem, libs, args))
    cells.append(" ".join(plank_plan or []))
    return "| " + " | ".join(cells) + " |"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plank_root", type=Path, help="a plank checkout (its benchmarks/ folder)")
    parser.add_argument("--seconds", type=float, default=40.0)
    parser.add_argument("--memory-gib", type=float, default=3.0)
    parser.add_argument("--only", default="", help="instances whose path contains this")
    parser.add_argument("--max-depth", type=int, default=None)
    parser.add_argument("--repeats", type=int, default=1, help="runs per instance (median)")
    parser.add_argument("--search", default="bfs", help="epistemica plan's --search")
    parser.add_argument("--plank", type=Path, help="plank's executable: validate each plan")
    parser.add_argument("--plank-bfs", type=Path, help="plank's bfs_planner: run it too")
    args = parser.parse_args(argv)
    for given in (args.plank, args.plank_bfs):
        if given is not None and not given.is_file():
            parser.error(f"{given} is not a file (build plank first: see its README)")
    root = args.plank_root / "benchmarks"
    head = ["instance", "exit", "answer", "wall s", "CPU s"]
    head += ["plank validate"] if args.plank else []
    head += ["plank BFS"] if args.plank_bfs else []
    head += ["plan (plank's names)"]
    print("| " + " | ".join(head) + " |")
    print("|" + "|".join("---:" if h in ("exit", "wall s", "CPU s") else "---" for h in head) + "|")
    for domain in sorted(root.glob("domains/*/*.epddl")):
        for problem in sorted((domain.parent / "instances").rglob("*.epddl")):
            name = problem.relative_to(root / "domains")
            if args.only in str(name):
                print(row(domain, problem, name, args), flush=True)


if __name__ == "__main__":
    main()
