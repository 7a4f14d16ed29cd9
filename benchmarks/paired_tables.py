"""Paired tables of levels run on the same trials: success with Wilson intervals, median and
mean completion with paired bootstrap intervals, win/tie/loss counts.

A *trial* is a (mission, trial seed) pair; every level ran on every trial. Completion is the
step a trial ended (a failure counts at its step limit), so the medians and means compare
every trial, solved or not. Intervals of differences resample whole missions (with their
trial seeds) from a seeded :class:`numpy.random.Generator`: trials of one mission are not
independent.

    >>> rows = {("m1", 0): {"a": (1, 10), "b": (1, 12)}, ("m2", 0): {"a": (0, 50), "b": (1, 40)}}
    >>> pair(rows, "a", "b", np.random.default_rng(0), resamples=200).wins
    1
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from epistemica.sim.study.report import wilson_interval

__all__ = ["Pair", "pair", "success_table", "versus_table"]


class Pair(NamedTuple):
    """``a`` against ``b`` on the trials both ran: differences are ``b - a`` (positive: ``a``
    is faster), each with a 95 % bootstrap interval; ``wins``: trials ``a`` ended sooner."""

    trials: int
    median_a: float
    median_b: float
    median_diff: tuple[float, float, float]
    mean_diff: tuple[float, float, float]
    wins: int
    ties: int
    losses: int


def _steps(rows: dict, level: str, keys: Sequence) -> np.ndarray:
    return np.array([rows[k][level][1] for k in keys], dtype=float)


def pair(rows: dict, a: str, b: str, rng: np.random.Generator, resamples: int = 2000) -> Pair:
    """Level ``a`` against ``b``; ``rows[(mission, seed)][level] = (success, steps)``."""
    keys = sorted(k for k, r in rows.items() if a in r and b in r)
    sa, sb = _steps(rows, a, keys), _steps(rows, b, keys)
    missions = sorted({k[0] for k in keys})
    index = {m: [i for i, k in enumerate(keys) if k[0] == m] for m in missions}
    med, mean = [], []
    for _ in range(resamples):
        pick = rng.integers(0, len(missions), size=len(missions))
        idx = np.concatenate([index[missions[p]] for p in pick])
        med.append(np.median(sb[idx]) - np.median(sa[idx]))
        mean.append(np.mean(sb[idx] - sa[idx]))

    def interval(point: float, draws: list) -> tuple[float, float, float]:
        low, high = np.percentile(draws, [2.5, 97.5])
        return float(point), float(low), float(high)

    return Pair(
        len(keys),
        float(np.median(sa)),
        float(np.median(sb)),
        interval(np.median(sb) - np.median(sa), med),
        interval(np.mean(sb - sa), mean),
        int((sa < sb).sum()),
        int((sa == sb).sum()),
        int((sa > sb).sum()),
    )


def success_table(rows: dict, levels: Sequence[str]) -> list[str]:
    """Markdown: per level, trials, success [95 % Wilson], median and mean completion."""
    out = [
        "| level | trials | success [95 % CI] | median steps | mean steps |",
        "|---|---:|---|---:|---:|",
    ]
    for level in levels:
        got = [r[level] for r in rows.values() if level in r]
        if not got:
            continue
        ok = sum(s for s, _ in got)
        low, high = wilson_interval(ok, len(got))
        steps = np.array([t for _, t in got], dtype=float)
        out.append(
            f"| {level} | {len(got)} | {100 * ok / len(got):.1f} % "
            f"[{100 * low:.1f}, {100 * high:.1f}] | {np.median(steps):.1f} | "
            f"{steps.mean():.1f} |"
        )
    return out


def versus_table(
    rows: dict, focus: str, levels: Sequence[str], rng: np.random.Generator
) -> list[str]:
    """Markdown: ``focus`` against each other level, paired (differences: other − focus)."""
    out = [
        f"| {focus} vs | trials | median steps ({focus} / other) | median diff [95 % CI] | "
        f"mean diff [95 % CI] | {focus} W / T / L |",
        "|---|---:|---|---|---|---|",
    ]
    for level in levels:
        if level == focus:
            continue
        p = pair(rows, focus, level, rng)
        if not p.trials:
            continue
        md, mn = p.median_diff, p.mean_diff
        out.append(
            f"| {level} | {p.trials} | {p.median_a:.1f} / {p.median_b:.1f} | "
            f"{md[0]:+.1f} [{md[1]:+.1f}, {md[2]:+.1f}] | "
            f"{mn[0]:+.1f} [{mn[1]:+.1f}, {mn[2]:+.1f}] | {p.wins} / {p.ties} / {p.losses} |"
        )
    return out
