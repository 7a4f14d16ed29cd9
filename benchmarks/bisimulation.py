"""Bisimulation contraction at scale: ``minimize`` on models of up to millions of worlds.

Three families of models, each with 3 agents, built from a seeded numpy Generator:

- ``partitions``: n worlds, 3 atoms with random values, each agent's knowledge a random
  partition into classes of about 8 worlds (S5); designated world 0. Few valuations and
  many look-alike classes: contraction takes several rounds and merges most worlds.
- ``beliefs``: the same worlds, each agent's belief relation a random KD45-style
  relation (every world of a partition class points at a random nonempty subset of it),
  stored as sparse arrows; knowledge is the partition.
- ``copies``: n / 1000 copies of a random S5 model of 1000 worlds, each agent's class of
  a world made of copies of its base class (in 8 copies): every copy of a world is
  bisimilar to it, so the model contracts to at most 1000 worlds.
- ``chain``: a path of n worlds with p only at its end (every world distinguished by its
  distance to p): one splitting round per world, the worst case of round-based refinement.

The script prints, per family and size, the worlds before and after, and the median wall
and CPU (process) time of ``--repeat`` runs of ``minimize`` (the generation of the model is
not timed; on a machine shared with other jobs the CPU time is the steadier figure). Run
it in a checkout of another commit for a "before" column (it uses public names only).

Usage: ``python benchmarks/bisimulation.py [--sizes 10000 100000 1000000] [--repeat 3]``
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np
import scipy.sparse as sp

from epistemica.del_ import KripkeModel
from epistemica.del_.explicit.relations import Arrows, Partition

AGENTS = ("a", "b", "c")


def _partition(rng: np.random.Generator, n: int, size: int = 8) -> Partition:
    return Partition(rng.integers(0, max(1, n // size), n))


def partitions(n: int, rng: np.random.Generator) -> KripkeModel:
    """Random S5 model: 3 atoms, each agent a partition into classes of about 8 worlds."""
    valuation = rng.random((n, 3)) < 0.5
    rel = {a: _partition(rng, n) for a in AGENTS}
    return KripkeModel.from_arrays(None, ("p", "q", "r"), valuation, AGENTS, rel, rel, [0])


def beliefs(n: int, rng: np.random.Generator) -> KripkeModel:
    """Random KD45-style beliefs inside random S5 knowledge."""
    valuation = rng.random((n, 3)) < 0.5
    know = {a: _partition(rng, n) for a in AGENTS}
    rel = {}
    for a in AGENTS:
        labels = know[a].labels
        believed = rng.random(n) < 0.5
        believed[np.unique(labels, return_index=True)[1]] = True  # each class believes one
        order = np.argsort(labels, kind="stable")
        rows, cols = [], []
        sorted_labels = labels[order]
        starts = np.flatnonzero(np.r_[True, sorted_labels[1:] != sorted_labels[:-1]])
        bounds = np.r_[starts, n]
        for s, e in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True):
            members = order[s:e]
            targets = members[believed[members]]
            rows.append(np.repeat(members, len(targets)))
            cols.append(np.tile(targets, len(members)))
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        matrix = sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(n, n))
        rel[a] = Arrows(matrix)
    return KripkeModel.from_arrays(None, ("p", "q", "r"), valuation, AGENTS, rel, know, [0])


def copies(n: int, rng: np.random.Generator, base: int = 1000) -> KripkeModel:
    """n / base copies of a random S5 model of ``base`` worlds, wired across copies.

    World ``(i, c)`` (base world i, copy c) has i's valuation; for each agent its class is
    (i's base class, c's group of 8 copies; the agents group copies with different
    offsets, so every copy is reachable), so its successors are copies of i's base
    successors: every copy of i is bisimilar to i and the model contracts to (at most)
    ``base`` worlds, after as many rounds as the base model needs.
    """
    n_copies = max(1, n // base)
    valuation = np.tile(rng.random((base, 3)) < 0.5, (n_copies, 1))
    rel = {}
    for offset, agent in zip((0, 3, 5), AGENTS, strict=True):
        group = np.repeat((np.arange(n_copies) + offset) // 8, base)
        labels = np.tile(rng.integers(0, base // 4, base), n_copies)
        rel[agent] = Partition(labels * (n_copies // 8 + 2) + group)
    return KripkeModel.from_arrays(None, ("p", "q", "r"), valuation, AGENTS, rel, rel, [0])


def chain(n: int, rng: np.random.Generator) -> KripkeModel:
    """A path 0 -> 1 -> ... -> n-1 for every agent, p true only at n-1."""
    valuation = np.zeros((n, 1), dtype=bool)
    valuation[-1, 0] = True
    rows, cols = np.arange(n - 1), np.arange(1, n)
    matrix = sp.csr_matrix((np.ones(n - 1, dtype=bool), (rows, cols)), shape=(n, n))
    rel = {a: Arrows(matrix) for a in AGENTS}
    return KripkeModel.from_arrays(None, ("p",), valuation, AGENTS, rel, rel, [0])


FAMILIES = {"partitions": partitions, "copies": copies, "beliefs": beliefs, "chain": chain}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    parser.add_argument("--families", nargs="+", default=list(FAMILIES), choices=FAMILIES)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--chain-max", type=int, default=100_000, help="largest chain")
    args = parser.parse_args()
    print(
        f"Python {platform.python_version()}, {platform.machine()}; median of {args.repeat} "
        f"runs of minimize; 3 agents; seed {args.seed}\n"
    )
    print("| family | worlds | edges | worlds after | median s (wall) | median s (CPU) |")
    print("|---|---:|---:|---:|---:|---:|")
    for family in args.families:
        for n in args.sizes:
            if family == "chain" and n > args.chain_max:
                continue
            model = FAMILIES[family](n, np.random.default_rng(args.seed))
            edges = sum(
                len(model.relation(a, kind).edges()[0])
                if not isinstance(model.relation(a, kind), Partition)
                else model.n_worlds
                for a in model.agents
                for kind in ("belief", "knowledge")
                if kind == "belief" or model.relation(a, kind) is not model.relation(a)
            )
            times, cpu, small = [], [], None
            for _ in range(args.repeat):
                fresh = KripkeModel.from_arrays(
                    None,
                    model.atoms,
                    model.valuation,
                    model.agents,
                    dict(model.belief_relations),
                    dict(model.knowledge_relations),
                    model.designated_positions,
                )
                start, start_cpu = time.perf_counter(), time.process_time()
                small = fresh.minimize()
                times.append(time.perf_counter() - start)
                cpu.append(time.process_time() - start_cpu)
            print(
                f"| {family} | {model.n_worlds:,} | {edges:,} | {small.n_worlds:,} | "
                f"{statistics.median(times):.2f} | {statistics.median(cpu):.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
