"""The generated benchmark's paired statistics (benchmarks/paired_tables.py) against values
worked by hand."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from paired_tables import pair, success_table, versus_table

# three missions, two trial seeds each: (success, steps) of levels a and b
ROWS = {
    ("m1", 0): {"a": (1, 10), "b": (1, 14)},
    ("m1", 1): {"a": (1, 12), "b": (1, 12)},
    ("m2", 0): {"a": (1, 20), "b": (0, 100)},
    ("m2", 1): {"a": (0, 100), "b": (1, 30)},
    ("m3", 0): {"a": (1, 8), "b": (1, 9)},
    ("m3", 1): {"a": (1, 9), "b": (1, 7)},
}


def test_pair_counts_and_differences_by_hand():
    p = pair(ROWS, "a", "b", np.random.default_rng(0), resamples=500)
    # a: 10 12 20 100 8 9 (sorted 8 9 10 12 20 100: median 11); b: 14 12 100 30 9 7
    # (sorted 7 9 12 14 30 100: median 13); b - a: 4 0 80 -70 1 -2 (mean 13/6)
    assert (p.trials, p.median_a, p.median_b) == (6, 11.0, 13.0)
    assert p.median_diff[0] == 2.0 and np.isclose(p.mean_diff[0], 13 / 6)
    assert (p.wins, p.ties, p.losses) == (3, 1, 2)
    for _, low, high in (p.median_diff, p.mean_diff):
        assert low <= high
    # resampling whole missions: the mean difference of any resample lies between the
    # missions' own means (2, 5, -0.5)
    assert -0.5 - 1e-9 <= p.mean_diff[1] and p.mean_diff[2] <= 5 + 1e-9
    again = pair(ROWS, "a", "b", np.random.default_rng(0), resamples=500)
    assert again == p  # a seeded Generator: the same intervals


def test_tables_show_wilson_intervals_and_the_paired_row():
    text = "\n".join(success_table(ROWS, ["a", "b"]))
    # a: 5 of 6; Wilson 95 %: centre (5/6 + 1.92/6) / (1 + 3.84/6), [43.6, 97.0]
    assert "| a | 6 | 83.3 % [43.6, 97.0] | 11.0 | 26.5 |" in text
    row = versus_table(ROWS, "a", ["a", "b"], np.random.default_rng(1))[-1]
    assert row.startswith("| b | 6 | 11.0 / 13.0 | +2.0 [") and row.endswith("| 3 / 1 / 2 |")
