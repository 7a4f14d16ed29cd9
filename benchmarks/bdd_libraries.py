"""Two BDD libraries on muddy children: dd (CUDD bindings) against oxidd (Rust).

The raw knowledge-structure loop, without epistemica: the state law starts as "at least
one child is muddy"; each round computes, per child i, Kw_i m_i = forall m_i (law -> m_i)
or forall m_i (law -> ~m_i), stops when every child knows at the all-muddy state, and
otherwise conjoins "nobody knows" to the law (n - 1 rounds, asserted). dd.cudd is timed
with CUDD's dynamic reordering on (dd's default) and off.

Usage: python benchmarks/bdd_libraries.py [--sizes 20,40,60,100] [--repeat 3]
(needs ``pip install dd``; dd is not a dependency of epistemica).
"""

from __future__ import annotations

import argparse
import statistics
import time


def with_dd(n: int, reordering: bool) -> int:
    from dd import cudd

    bdd = cudd.BDD()
    names = [f"m{i}" for i in range(n)]
    bdd.declare(*names)
    bdd.configure(reordering=reordering)
    muddy = [bdd.var(x) for x in names]
    law = bdd.false
    for m in muddy:
        law |= m
    everyone = dict.fromkeys(names, True)
    rounds = 0
    while True:
        kw = [
            bdd.forall([x], ~law | m) | bdd.forall([x], ~law | ~m)
            for x, m in zip(names, muddy, strict=True)
        ]
        know = bdd.true
        for k in kw:
            know &= k
        if bdd.let(everyone, know) == bdd.true:
            return rounds
        for k in kw:
            law &= ~k
        rounds += 1


def with_oxidd(n: int) -> int:
    from oxidd.bdd import BDDManager

    manager = BDDManager(1 << 24, 1 << 20, 1)
    manager.add_vars(n)
    muddy = [manager.var(i) for i in range(n)]
    law = manager.false()
    everyone = manager.true()
    for m in muddy:
        law, everyone = law | m, everyone & m
    rounds = 0
    while True:
        kw = [(~law | m).forall(m) | (~law | ~m).forall(m) for m in muddy]
        know = manager.true()
        for k in kw:
            know &= k
        if not (everyone & ~know).satisfiable():
            return rounds
        for k in kw:
            law &= ~k
        rounds += 1


def median(run, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="20,40,60,100")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    runs = {
        "dd.cudd (reordering)": lambda n: with_dd(n, True),
        "dd.cudd (no reordering)": lambda n: with_dd(n, False),
        "oxidd": with_oxidd,
    }
    print("| children | " + " | ".join(f"{name}: median s" for name in runs) + " |")
    print("|---:|" + "---:|" * len(runs))
    for n in (int(x) for x in args.sizes.split(",")):
        cells = []
        for run in runs.values():
            if run(n) != n - 1:
                raise AssertionError(f"{n} children should know after {n - 1} rounds")
            cells.append(f"{median(lambda run=run, n=n: run(n), args.repeat):.3f}")
        print(f"| {n} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
