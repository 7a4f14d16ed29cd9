"""Multitask mean completion step (failures count as 150) beside the published numbers.

Usage: ``python benchmarks/multitask_comparison.py runs/multitask.sqlite``; prints a
markdown table with 95 % normal intervals of the means. A file with the released-algorithm
levels (``paper-first``, ``paper-higher``) gets their table beside the published first and
higher order, with ``*`` where the published mean falls outside our interval.
"""

from __future__ import annotations

import sys

import numpy as np

from epistemica.sim.store import read_rows

# paper-results.md, mean completion step (150 for failures), 150 trials per team size.
PUBLISHED_ZERO = {2: 107.4, 3: 99.4, 4: 89.8, 5: 81.6, 6: 71.9, 7: 68.1, 8: 61.9}
PUBLISHED_HIGHER = {2: 97.4, 3: 73.2, 4: 61.9, 5: 56.0, 6: 51.4, 7: 48.8, 8: 49.2}
PUBLISHED_FIRST = {2: 93.6, 3: 74.2, 4: 69.1, 5: 67.1, 6: 61.6, 7: 58.3, 8: 54.0}
PAPER_LEVELS = {"paper-first": PUBLISHED_FIRST, "paper-higher": PUBLISHED_HIGHER}


def against_published(values: list[float], published: float | None) -> str:
    """``mean ± half-width (published)``, starred when the published mean is outside."""
    if not values:
        return "-"
    mean = float(np.mean(values))
    half = 1.96 * np.std(values, ddof=1) / np.sqrt(len(values)) if len(values) > 1 else 0.0
    if published is None:
        return f"{mean:.1f} ± {half:.1f}"
    star = " *" if abs(mean - published) > half else ""
    return f"{mean:.1f} ± {half:.1f} ({published}){star}"


def mean_ci(values: list[float]) -> str:
    return against_published(values, None)


def paper_table(rows: list[dict]) -> None:
    print(
        "| robots | trials | paper-first (published first) | paper-higher (published higher) "
        "| successes first / higher |"
    )
    print("|---|---|---|---|---|")
    for n in sorted({r["robots"] for r in rows}):
        cells, done = [], []
        for level, published in PAPER_LEVELS.items():
            mine = [r for r in rows if r["robots"] == n and r["reasoning"] == level]
            cells.append(
                against_published([r["completion_step"] or 150 for r in mine], published.get(n))
            )
            done.append(f"{sum(r['success'] for r in mine)}/{len(mine)}")
        trials = sum(1 for r in rows if r["robots"] == n and r["reasoning"] == "paper-first")
        print(f"| {n} | {trials} | {cells[0]} | {cells[1]} | {' / '.join(done)} |")


def main(path: str) -> None:
    rows = read_rows(path)
    if {r["reasoning"] for r in rows} & set(PAPER_LEVELS):
        paper_table(rows)
        rows = [r for r in rows if r["reasoning"] not in PAPER_LEVELS]
        if not rows:
            return
    print(
        "| robots | zero (published zero) | convention | third | published higher | "
        "third successes |"
    )
    print("|---|---|---|---|---|---|")
    for n in sorted({r["robots"] for r in rows}):
        cell = {}
        for level in ("zero", "convention", "third"):
            mine = [r for r in rows if r["robots"] == n and r["reasoning"] == level]
            cell[level] = mine
        done = {k: [r["completion_step"] or 150 for r in v] for k, v in cell.items()}
        ok = sum(r["success"] for r in cell["third"])
        print(
            f"| {n} | {mean_ci(done['zero'])} ({PUBLISHED_ZERO.get(n, '-')}) | "
            f"{mean_ci(done['convention'])} | {mean_ci(done['third'])} | "
            f"{PUBLISHED_HIGHER.get(n, '-')} | {ok}/{len(cell['third'])} |"
        )


if __name__ == "__main__":
    main(sys.argv[1])
