"""The large fuzz run: 10,000 mutated specs and command lines, in worker processes.

    python benchmarks/fuzz_cli.py [--cases 10000] [--workers 2] [--seed 1]

Each worker runs tests/fuzz_corpus.py on its share of the cases (seeds ``seed + k``),
under a 4 GiB address-space limit and a 20 s limit per case; the totals by exit status
(0, 1, 2; 3 would be an internal error, -1 a case over its time limit) are printed with
the slowest case and every bad one. docs/performance.md has the last run's figures.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

CORPUS = Path(__file__).resolve().parents[1] / "tests" / "fuzz_corpus.py"


def _worker(seed: int, cases: int) -> dict:
    out = subprocess.run(
        [sys.executable, str(CORPUS), "--cases", str(cases), "--seed", str(seed)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    if out.returncode != 0:
        return {"cases": cases, "counts": {"worker-died": cases}, "bad": [out.stderr[-500:]],
                "slowest_seconds": 0, "slowest": None, "max_rss_mib": 0}  # fmt: skip
    return json.loads(out.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--batch", type=int, default=500, help="cases per worker process")
    args = parser.parse_args()
    batches = [
        (args.seed + k, min(args.batch, args.cases - k * args.batch))
        for k in range((args.cases + args.batch - 1) // args.batch)
    ]
    start = time.perf_counter()
    with ThreadPoolExecutor(args.workers) as pool:
        results = list(pool.map(lambda b: _worker(*b), batches))
    counts: dict[str, int] = {}
    for r in results:
        for code, n in r["counts"].items():
            counts[code] = counts.get(code, 0) + n
    slowest = max(results, key=lambda r: r["slowest_seconds"])
    summary = {
        "cases": sum(r["cases"] for r in results),
        "counts": dict(sorted(counts.items())),
        "bad": [b for r in results for b in r["bad"]],
        "slowest_seconds": slowest["slowest_seconds"],
        "slowest": slowest["slowest"],
        "max_rss_mib": max(r["max_rss_mib"] for r in results),
        "wall_seconds": round(time.perf_counter() - start, 1),
    }
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()
