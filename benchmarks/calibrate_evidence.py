"""Calibrate the evidence scales (issue 19 §1): the ``eta`` and ``eta_bearing`` that make
the controller's salience ``exp(-h / eta)`` best predict where robots actually end.

For every solved trial of a level on the given seeds, and every step of it, the
evidence a robot ``j`` gives for each goal ``g`` is ``exp(-d_jg / eta)`` (range: the
distance from ``j`` to ``g``) or, seen from a bearing robot ``i``, ``exp(-a_ijg /
eta_bearing)`` (the angle at ``i`` between ``j`` and ``g``); the goal ``j`` ends at is
scored under ``softmax_g`` of that evidence, as one chain of the controller's likelihood
(docs/aif.md). The scale of largest mean log likelihood per step is the calibrated one;
the script prints it beside the defaults (50 m, 1 rad) and the log likelihood of both.

    python benchmarks/calibrate_evidence.py --seeds 1000-1019
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.special import log_softmax

from epistemica.aif.evidence import DEFAULT_ETA, DEFAULT_ETA_BEARING
from epistemica.sim import Scenario, simulate

CELLS = (("rendezvous", 3), ("rendezvous", 5), ("allocation", 3), ("allocation", 5))


def samples(level: str, seeds) -> tuple[list, list]:
    """``(range, bearing)`` samples: ``(h (m,), chosen goal)`` per robot, step and viewpoint."""
    ranged, bearing = [], []
    for mission, n in CELLS:
        for seed in seeds:
            scenario = Scenario.paper(mission, n, n, seed=seed)
            trial = simulate(scenario, level, seed=seed)
            if not trial.success:
                continue
            goals = scenario.goals
            final = trial.trajectory[-1, :, :2]
            chosen = np.argmin(np.hypot(*(final[:, None] - goals[None]).transpose(2, 0, 1)), 1)
            for pose in trial.trajectory[:-1]:
                xy = pose[:, :2]
                distance = np.hypot(*(xy[:, None] - goals[None]).transpose(2, 0, 1))  # (n, m)
                ranged += [(distance[j], chosen[j]) for j in range(n)]
                for i in np.flatnonzero(np.asarray(scenario.sensors) == "bearing"):
                    to_robot = xy - xy[i]
                    to_goal = goals - xy[i]
                    for j in range(n):
                        if j == i or np.hypot(*to_robot[j]) < 1e-9:
                            continue
                        cross = to_robot[j, 0] * to_goal[:, 1] - to_robot[j, 1] * to_goal[:, 0]
                        dot = to_robot[j] @ to_goal.T
                        bearing.append((np.arctan2(np.abs(cross), dot), chosen[j]))
    return ranged, bearing


def mean_log_likelihood(scale: float, data) -> float:
    """Mean over ``data`` of the log probability of the chosen goal (any number of goals)."""
    total = 0.0
    for m in {len(h) for h, _ in data}:
        h = np.array([d for d, _ in data if len(d) == m])
        chosen = np.array([c for d, c in data if len(d) == m])
        scores = log_softmax(np.exp(-h / scale), axis=1)
        total += float(scores[np.arange(len(chosen)), chosen].sum())
    return total / len(data)


def calibrate(data, bounds) -> float:
    result = minimize_scalar(
        lambda log_scale: -mean_log_likelihood(np.exp(log_scale), data),
        bounds=np.log(bounds),
        method="bounded",
    )
    return float(np.exp(result.x))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1000-1019", help="first-last (inclusive)")
    parser.add_argument("--level", default="rules-third")
    args = parser.parse_args()
    first, last = map(int, args.seeds.split("-"))
    ranged, bearing = samples(args.level, range(first, last + 1))
    for name, data, default, bounds in (
        ("eta", ranged, DEFAULT_ETA, (0.1, 1000.0)),
        ("eta_bearing", bearing, DEFAULT_ETA_BEARING, (0.01, 100.0)),
    ):
        best = calibrate(data, bounds)
        uniform = -float(np.mean([np.log(len(h)) for h, _ in data]))
        print(
            f"{name}: {len(data)} samples; calibrated {best:.3g} "
            f"(mean log likelihood {mean_log_likelihood(best, data):.4f}), "
            f"default {default:g} ({mean_log_likelihood(default, data):.4f}), "
            f"uniform {uniform:.4f}"
        )


if __name__ == "__main__":
    main()
