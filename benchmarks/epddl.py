"""EPDDL benchmarks: does each instance parse, its shortest plan, the time, plank's verdict.

Runs a directory of EPDDL benchmarks laid out as plank's ``benchmarks/domains/`` (one folder
per domain: the domain file, and the problems under ``instances/``, at any depth), with the
action-type libraries of ``--libraries`` (default: a ``libraries`` folder next to the
domains folder). For each instance it prints whether epistemica reads it (and the error if
not), the length of the plan breadth-first search finds (the shortest) and the planning
time (median of ``--repeat`` runs, each in a process of its own stopped after
``--timeout`` seconds). With ``--plank PATH`` (a plank executable you built), each plan is
also given to ``plank validate`` and its answer is printed. ``docs/planning.md`` section
"EPDDL benchmarks" is this script's output (``--markdown``).

plank's benchmarks are not shipped with epistemica; fetch them with plank's repository.

Usage: ``python benchmarks/epddl.py PLANK/benchmarks/domains [--plank PLANK/build/plank]
[--max-depth 10] [--timeout 600] [--repeat 3] [--markdown]``
"""

from __future__ import annotations

import argparse
import multiprocessing
import platform
import re
import statistics
import subprocess
import time
from pathlib import Path

from epistemica.del_ import plan_with_stats
from epistemica.del_.errors import EpistemicaError
from epistemica.del_.formats.epddl import load_epddl


def instances(root: Path) -> list[tuple[str, Path, Path]]:
    """(domain name, domain file, problem file) for every instance under ``root``."""
    found = []
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        domains = sorted(folder.glob("*.epddl"))
        problems = sorted((folder / "instances").rglob("*.epddl"))
        if len(domains) != 1:
            continue
        found += [(folder.name, domains[0], p) for p in problems]
    return found


def libraries_for(domain: Path, available: list[Path]) -> list[Path]:
    """The libraries a domain names (``(:action-type-libraries ...)``, found by file name);
    for a domain that names none, the first library that defines every action type it
    uses (plank rejects two libraries that define one name)."""
    text = "\n".join(line.split(";", 1)[0] for line in domain.read_text().splitlines())
    match = re.search(r"\(:action-type-libraries([^)]*)\)", text)
    if match:
        names = match.group(1).split()
        return [p for p in available if p.stem in names] or available
    used = set(re.findall(r":action-type\s*\(\s*([^\s()]+)", text)) - {"basic"}
    if not used:
        return []
    for library in available:
        defined = set(re.findall(r"\(:action-type\s+([^\s()]+)", library.read_text()))
        if used <= defined:
            return [library]
    return available


def solve(domain: Path, problem: Path, libraries: list[Path], max_depth: int, out) -> None:
    """Parse and plan one instance; put the outcome on the queue ``out``."""
    start = time.perf_counter()
    try:
        task = load_epddl(domain, problem, libraries)
    except EpistemicaError as exc:
        out.put({"parses": False, "why": str(exc).splitlines()[0]})
        return
    parse = time.perf_counter() - start
    spec = task.spec
    if spec.goal is None:
        out.put({"parses": True, "parse": parse, "why": "no goal"})
        return
    result = plan_with_stats(spec.model, spec.actions, spec.goal, max_depth=max_depth)
    out.put(
        {
            "parses": True,
            "parse": parse,
            "worlds": spec.model.n_worlds,
            "actions": len(spec.actions),
            "plan": result.plan,
            "plank_plan": task.plank_plan(result.plan) if result.plan is not None else None,
            "complete": result.complete,
            "seconds": result.seconds,
            "states": result.distinct,
        }
    )


def run(domain: Path, problem: Path, libraries: list[Path], args) -> dict:
    """One run in a process of its own, stopped after ``args.timeout`` seconds."""
    queue: multiprocessing.Queue = multiprocessing.Queue()
    process = multiprocessing.Process(
        target=solve, args=(domain, problem, libraries, args.max_depth, queue)
    )
    start = time.perf_counter()
    process.start()
    process.join(args.timeout)
    if process.is_alive():
        process.terminate()
        process.join()
        return {"parses": None, "why": f"timeout ({args.timeout:g} s)"}
    outcome = queue.get() if not queue.empty() else {"parses": None, "why": "crashed"}
    outcome["wall"] = time.perf_counter() - start
    return outcome


def plank_verdict(
    plank: Path, domain: Path, problem: Path, libraries, plan: list[str], timeout: float = 600
) -> str:
    """plank's ``validate`` answer on the plan: ``true``, or ``false (...)`` and why."""
    command = [str(plank), "validate", "-d", str(domain), "-p", str(problem)]
    if libraries:
        command += ["-l", *map(str, libraries)]
    command += ["-a", *plan] if plan else []
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return f"no answer within {timeout:g} s"
    lines = [ln for ln in (done.stdout + done.stderr).splitlines() if ln.strip()]
    verdicts = [ln.strip() for ln in lines if ln.strip().startswith(("true", "false"))]
    return verdicts[-1] if verdicts else (lines[-1] if lines else f"exit {done.returncode}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("domains", type=Path, help="a folder of domain folders")
    parser.add_argument("--libraries", type=Path, help="folder of action-type libraries")
    parser.add_argument("--plank", type=Path, help="a plank executable, to validate the plans")
    parser.add_argument("--max-depth", type=int, default=10)
    parser.add_argument("--timeout", type=float, default=600.0)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--only", nargs="*", default=[], help="instances whose path has these")
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()
    library_dir = args.libraries or args.domains.parent / "libraries"
    libraries = sorted(library_dir.glob("*.epddl")) if library_dir.is_dir() else []
    rows = []
    for name, domain, problem in instances(args.domains):
        label = f"{name}/{problem.relative_to(domain.parent / 'instances')}"
        if args.only and not any(word in str(problem) for word in args.only):
            continue
        chosen = libraries_for(domain, libraries)
        runs = [run(domain, problem, chosen, args) for _ in range(args.repeat)]
        first = runs[0]
        seconds = [r["seconds"] for r in runs if "seconds" in r]
        row = {"instance": label, **first}
        if seconds:
            row["seconds"] = statistics.median(seconds)
        if args.plank and first.get("plank_plan") is not None:
            plank_plan = first["plank_plan"]
            row["plank"] = plank_verdict(
                args.plank, domain, problem, chosen, plank_plan, args.timeout
            )
        rows.append(row)
        print(_line(row, args.markdown) if args.markdown else _text(row), flush=True)
    if args.markdown:
        python = f"{platform.python_implementation()} {platform.python_version()}"
        depth = f"BFS up to depth {args.max_depth}, median of {args.repeat}"
        print(f"\n({python}, {platform.machine()}; {depth})")


def _length(row: dict) -> str:
    if row.get("plan") is not None:
        return str(len(row["plan"]))
    if row.get("parses") and "complete" in row:
        return "no plan" if row["complete"] else "none within the depth"
    return "-"


def _text(row: dict) -> str:
    if not row.get("parses"):
        return f"{row['instance']}: does not parse: {row['why']}"
    tail = f", plank: {row['plank']}" if "plank" in row else ""
    time_taken = f"{row['seconds']:.2f} s" if "seconds" in row else row.get("why", "")
    plan = " ".join(row["plank_plan"]) if row.get("plank_plan") else ""
    return f"{row['instance']}: parses, plan length {_length(row)}, {time_taken}{tail}  {plan}"


def _line(row: dict, _markdown: bool) -> str:
    if not row.get("parses"):
        return f"| {row['instance']} | no: {row['why']} | | | | |"
    plan = " ".join(row["plank_plan"]) if row.get("plank_plan") else ""
    seconds = f"{row['seconds']:.2f}" if "seconds" in row else row.get("why", "")
    return (
        f"| {row['instance']} | yes | {_length(row)} | {row.get('plank', '')} | {seconds} "
        f"| {plan} |"
    )


if __name__ == "__main__":
    main()
