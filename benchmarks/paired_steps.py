"""Mean steps of two levels on the trials both solved (same seeds), from a sweep file.

Mean steps over each level's own successes flatter a level that fails its hard trials;
pairing by seed compares like with like.

Usage: ``python benchmarks/paired_steps.py runs/ours.sqlite third convention``
"""

from __future__ import annotations

import sys

import numpy as np

from epistemica.sim.study.store import read_rows


def main(path: str, a: str, b: str) -> None:
    rows = read_rows(path)
    by = {(r["mission"], r["robots"], r["goals"], r["reasoning"], r["seed"]): r for r in rows}
    cells = sorted({k[:3] for k in by})
    print(f"| mission | robots | goals | both solved | {a} steps | {b} steps | difference |")
    print("|---|---|---|---|---|---|---|")
    for cell in cells:
        seeds = sorted({k[4] for k in by if k[:3] == cell})
        pairs = [(by.get((*cell, a, s)), by.get((*cell, b, s))) for s in seeds]
        both = [
            (x["steps"], y["steps"]) for x, y in pairs if x and y and x["success"] and y["success"]
        ]
        if not both:
            continue
        sa, sb = np.mean(both, axis=0)
        print(
            f"| {cell[0]} | {cell[1]} | {cell[2]} | {len(both)} | {sa:.1f} | {sb:.1f} | "
            f"{sa - sb:+.1f} |"
        )


if __name__ == "__main__":
    main(*sys.argv[1:4])
