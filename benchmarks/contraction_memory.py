"""Peak memory of bisimulation contraction on the muddy children model (issue 38, item 8).

Two families of n agents over 2^n worlds, each agent ``c_i`` seeing every ``m_j`` but its
own ``m_i`` (an S5 partition into pairs), designated world "all muddy":

- ``muddy``: the model of :meth:`KripkeModel.from_observables`, every atom in the
  valuation. Every world has its own valuation, so nothing merges: 2^n worlds after.
- ``hidden``: the same worlds and relations, but only the last ``n - n // 2`` atoms in the
  valuation. Flipping any hidden bit maps the model onto itself and keeps the valuation,
  so worlds that agree on the visible atoms are bisimilar and worlds that disagree are
  not: exactly ``2^(n - n // 2)`` worlds after. This is the general refinement's work.

Each (family, n) runs in a fresh interpreter that builds the model, lists its arrays (what
any algorithm on it needs first), then calls ``minimize``; it prints the peak RSS before
and after ``minimize`` (``ru_maxrss``) and its wall time, and checks the number of worlds
after against the counts above. The target of issue 38 is a peak of at most 2 GiB at
n = 20 (measured 9.8 GiB before).

Usage: ``python benchmarks/contraction_memory.py [--sizes 12 16 20] [--families muddy hidden]``
"""

from __future__ import annotations

import argparse
import subprocess
import sys

_CHILD = """
import resource, sys, time
import numpy as np
from epistemica.del_ import KripkeModel

family, n = sys.argv[1], int(sys.argv[2])
atoms = [f"m{i}" for i in range(1, n + 1)]
observes = {f"c{i}": atoms[: i - 1] + atoms[i:] for i in range(1, n + 1)}
model = KripkeModel.from_observables(atoms, observes, designated=atoms)
if family == "hidden":
    visible = n // 2
    model = KripkeModel.from_arrays(
        None, tuple(model.atoms[visible:]), np.ascontiguousarray(model.valuation[:, visible:]),
        model.agents, dict(model.belief_relations), dict(model.knowledge_relations),
        model.designated_positions,
    )
    expected = 2 ** (n - visible)
else:
    expected = 2**n
model.valuation, model.belief_relations  # the arrays every algorithm reads
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
start = time.perf_counter()
after = model.minimize().n_worlds
seconds = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
assert after == expected, (after, expected)
print(model.n_worlds, after, before, peak, seconds)
"""


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[12, 16, 20])
    parser.add_argument("--families", nargs="+", default=["muddy", "hidden"])
    args = parser.parse_args(argv)
    print("| family | agents | worlds | after | RSS before MiB | peak RSS MiB | minimize s |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for family in args.families:
        for n in args.sizes:
            done = subprocess.run(
                [sys.executable, "-c", _CHILD, family, str(n)],
                capture_output=True,
                text=True,
                check=False,
            )
            if done.returncode:
                print(f"| {family} | {n} | failed: {done.stderr.strip()[-300:]} |||||")
                continue
            worlds, after, before, peak, seconds = done.stdout.split()
            print(
                f"| {family} | {n} | {int(worlds):,} | {int(after):,} | "
                f"{int(before) / 1024:.0f} | {int(peak) / 1024:.0f} | {float(seconds):.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
