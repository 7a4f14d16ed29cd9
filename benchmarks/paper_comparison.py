"""Published success rates beside ours, from sweep result files.

Reads the SQLite files of the reproduction sweeps (see docs/results.md for the commands)
and prints, per cell, the published rate (paper-results.md, 50 trials per cell) and ours
with its 95 % Wilson interval, marking cells where the published rate falls outside it.

Usage: ``python benchmarks/paper_comparison.py runs/paper-rendezvous.sqlite
runs/paper-allocation.sqlite``
"""

from __future__ import annotations

import sys

from epistemica.sim.study.report import summarise
from epistemica.sim.study.store import read_rows

# paper-results.md: (robots, goals) -> (zero, first, higher), percent of 50 trials.
RENDEZVOUS = {
    (2, 2): (48, 72, 90),
    (2, 3): (40, 88, 98),
    (2, 4): (32, 90, 96),
    (2, 5): (18, 88, 98),
    (3, 2): (30, 8, 66),
    (3, 3): (22, 58, 78),
    (3, 4): (6, 74, 72),
    (3, 5): (2, 64, 62),
    (4, 2): (26, 18, 80),
    (4, 3): (16, 34, 78),
    (4, 4): (0, 36, 78),
    (4, 5): (0, 36, 74),
    (5, 2): (14, 10, 86),
    (5, 3): (8, 16, 78),
    (5, 4): (0, 28, 74),
    (5, 5): (0, 22, 64),
}
ALLOCATION = {
    (2, 2): (52, 100, 100),
    (3, 3): (12, 60, 72),
    (4, 4): (12, 28, 66),
    (5, 5): (0, 16, 58),
}
PUBLISHED = {"rendezvous": RENDEZVOUS, "allocation": ALLOCATION}
COLUMNS = (("zero", 0), ("paper-first", 1), ("paper-higher", 2), ("paper-higher-fixed", 2))


def main(paths: list[str]) -> None:
    cells = {
        (c.mission, c.robots, c.goals, c.reasoning): c
        for path in paths
        for c in summarise(read_rows(path))
    }
    print(
        "| mission | robots | goals | "
        + " | ".join(f"{name} (published)" for name, _ in COLUMNS)
        + " |"
    )
    print("|---|---|---|" + "---|" * len(COLUMNS))
    outside = total = 0
    for mission, table in PUBLISHED.items():
        for (n, m), rates in table.items():
            parts = []
            for name, k in COLUMNS:
                cell = cells.get((mission, n, m, name))
                if cell is None:
                    parts.append("-")
                    continue
                miss = not cell.low - 1e-9 <= rates[k] / 100 <= cell.high + 1e-9
                outside += miss
                total += 1
                parts.append(
                    f"{100 * cell.rate:.0f} [{100 * cell.low:.0f}, {100 * cell.high:.0f}]"
                    f" ({rates[k]}){' *' if miss else ''}"
                )
            print(f"| {mission} | {n} | {m} | " + " | ".join(parts) + " |")
    print(f"\n* published rate outside our 95 % interval: {outside} of {total} cells")


if __name__ == "__main__":
    main(sys.argv[1:])
