"""Benchmark: wall time of short ``epistemica`` commands, start-up included.

Each command is run as a fresh process (the installed ``epistemica`` console script next
to this Python, else ``python -m epistemica``) ``--repeats`` times after one warm-up run
(which fills the file cache and, if enabled, lark's grammar cache); the median and the
minimum are reported. Targets from issue 12: ``--help`` ≤ 0.15 s, ``check
specs/puzzles/muddy_children.epi`` ≤ 0.4 s; from issue 38, ``check
specs/puzzles/coin_toss.epi`` (a small spec) ≤ 0.25 s on an idle machine. Also printed:
the seconds ``python -c pass`` takes, the floor every command pays, and each command's
median CPU seconds (user + system of the child), the steadier figure on a machine that
other jobs share (wall time there includes waiting for a core), and the load average before
and after the runs.

Children run without ``PYTHONDONTWRITEBYTECODE`` (the warm-up run writes the bytecode
caches, as any installed or normally used package has them): with it set, every run
compiles the sixty-odd project modules a ``check`` imports from source, about 0.2 s of CPU
on this 2-core machine. ``--as-is`` keeps the environment unchanged.

Usage: ``python benchmarks/cli_startup.py [--repeats 11] [--as-is]``; prints a markdown table.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MUDDY = str(ROOT / "specs" / "puzzles" / "muddy_children.epi")
COIN = str(ROOT / "specs" / "puzzles" / "coin_toss.epi")

COMMANDS = {
    "python -c pass": ([sys.executable, "-c", "pass"], None),
    "epistemica --help": (["--help"], 0.15),
    "epistemica check muddy_children.epi": (["check", MUDDY], 0.4),
    "epistemica check coin_toss.epi": (["check", COIN], 0.25),
    "epistemica show muddy_children.epi": (["show", MUDDY, "--after", "father"], None),
    "epistemica plan muddy_children.epi": (["plan", MUDDY], None),
}


def command_line() -> list[str]:
    script = Path(sys.executable).with_name("epistemica")
    if script.exists():
        return [str(script)]
    found = shutil.which("epistemica")
    return [found] if found else [sys.executable, "-m", "epistemica"]


def _time(argv: list[str], env: dict[str, str] | None = None) -> tuple[float, float] | None:
    """Wall and CPU seconds of one run; None if the command failed (e.g. absent from an
    older version)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False, env=env
    )
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return (elapsed, cpu) if done.returncode == 0 else None


def main() -> None:
    options = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    options.add_argument("--repeats", type=int, default=11)
    options.add_argument("--as-is", action="store_true", help="keep PYTHONDONTWRITEBYTECODE")
    parsed = options.parse_args()
    repeats = parsed.repeats
    env = dict(os.environ)
    if not parsed.as_is:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
    base = command_line()
    caches = "off" if env.get("PYTHONDONTWRITEBYTECODE") else "on"
    print(
        f"command: {' '.join(base)}; {repeats} runs each after one warm-up; "
        f"bytecode caches {caches}; load average before {_load()}"
    )
    print("| command | median (s) | min (s) | median CPU (s) | target (s) |")
    print("|---|---|---|---|---|")
    for label, (args, target) in COMMANDS.items():
        argv = args if label.startswith("python") else [*base, *args]
        if _time(argv, env) is None:
            print(f"| `{label}` | failed | | | |")
            continue
        runs = [_time(argv, env) for _ in range(repeats)]
        times = [wall for wall, _ in runs]
        median = statistics.median(times)
        cpu = statistics.median(c for _, c in runs)
        verdict = "" if target is None else f"{target} ({'met' if median <= target else 'MISSED'})"
        print(f"| `{label}` | {median:.3f} | {min(times):.3f} | {cpu:.3f} | {verdict} |")
    print(f"\nload average after: {_load()} (the machine's 1, 5 and 15 minute averages)")


def _load() -> str:
    """The load averages: wall times on a shared machine include waiting for a core."""
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


if __name__ == "__main__":
    main()
