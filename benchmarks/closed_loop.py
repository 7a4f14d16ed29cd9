"""Closed-loop check of the controller: published geometries under fresh noise.

For each scenario (published-protocol geometries drawn from ``--geometries`` seeds, and
the hand-made symmetric scene), every level runs with ``--noise`` observation-noise seeds.
A scenario counts as solved by a level when it succeeds in at least 9 of 10 noise seeds.
The issue's target: third order solves every scenario the released higher-order code
(``paper-higher``) solves, and the symmetric scene in at least 8 of 10.

The symmetric scene: rendezvous, goals (10, 15) and (20, 15); a range robot at (5, 15),
nearest the first goal, and a bearing robot at (25, 15), nearest the second, both on the
line through the goals: the two meeting points cost the same total distance.

Usage: ``python benchmarks/closed_loop.py [--levels rules-third,paper-higher,convention]
[--robots 2,3,4,5] [--geometries 0-9] [--noise 10]``; prints a markdown table.
"""

from __future__ import annotations

import argparse

import numpy as np

from epistemica.sim import Scenario, simulate


def symmetric_scene() -> Scenario:
    """The hand-made tie: each robot nearest a different goal, equal total distances."""
    return Scenario(
        "rendezvous",
        [[5.0, 15.0, 0.0], [25.0, 15.0, np.pi]],
        [[10.0, 15.0], [20.0, 15.0]],
        ["range", "bearing"],
    )


def successes(scenario: Scenario, level: str, noise: int) -> int:
    return sum(simulate(scenario, level, seed=k).success for k in range(noise))


def seeds(text: str) -> range:
    low, _, high = text.partition("-")
    return range(int(low), int(high or low) + 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="rules-third,paper-higher,convention")
    parser.add_argument("--robots", default="2,3,4,5")
    parser.add_argument("--geometries", default="0-9")
    parser.add_argument("--noise", type=int, default=10)
    args = parser.parse_args()
    levels = args.levels.split(",")
    scenes = [("symmetric", symmetric_scene())]
    for n in map(int, args.robots.split(",")):
        for g in seeds(args.geometries):
            scenes.append(
                (f"rendezvous n={n} m={n} seed={g}", Scenario.paper("rendezvous", n, n, g))
            )
            scenes.append((f"allocation n={n} seed={g}", Scenario.paper("allocation", n, n, g)))
    print("| scenario | " + " | ".join(levels) + " |")
    print("|---|" + "---|" * len(levels))
    solved = dict.fromkeys(levels, 0)
    missed = []
    for name, scenario in scenes:
        counts = {level: successes(scenario, level, args.noise) for level in levels}
        for level, c in counts.items():
            solved[level] += c >= 0.9 * args.noise
        if "paper-higher" in counts and counts["paper-higher"] >= 0.9 * args.noise:
            if counts.get("rules-third", args.noise) < 0.9 * args.noise:
                missed.append(name)
        print(
            f"| {name} | " + " | ".join(f"{counts[v]}/{args.noise}" for v in levels) + " |",
            flush=True,
        )
    print()
    print("solved (>= 90 %): " + ", ".join(f"{v} {solved[v]}/{len(scenes)}" for v in levels))
    print("solved by paper-higher but not by third: " + (", ".join(missed) or "none"))


if __name__ == "__main__":
    main()
