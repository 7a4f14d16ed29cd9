"""Every goal switch of one planning trial, its margin split into the terms of ``G``.

Runs one trial inside :func:`epistemica.sim.policies.planning.recording_plans` and, at each
change of a robot's goal between two plans over the same goals, prints:

- the margin ``G(goal left) - G(goal taken)`` in nats, split into the time term
  ``E[T | formed] / tau``, the success term ``-success_weight ln P(formed)`` and the
  charges (commitment, convention); ``inf`` where the goal left is no longer in the
  robot's set (its knowledge changed, not its scores);
- which teammate's prediction carries the switch: the one whose row, put back to the
  robot's previous plan, removes the most of the margin; where the robot placed it at the
  two plans, how far that moved, and what the robot had read of its moves
  (``PlanningStage._read``) for the two goals it was predicted at.

The success term is recomputed from the predictions and the set the planner scored the
robot's own options with (captured from ``PlanContext.given`` for the one-robot chain).

Usage::

    python benchmarks/planning_switches.py specs/stress/allocation_hardest_10.epi \\
        --seed 1036 [--set plan_filter=true]

``docs/results/planning_wrong_decision.md`` ("Switches under noisy sightings") reads it.
"""

from __future__ import annotations

import argparse

import numpy as np
from planning_trace import traced_trial, trial_options

from epistemica.aif.plan_context import PlanContext
from epistemica.sim.policies.planning import WAIT


def _capture(log: list) -> None:
    """Record the own-options input of every plan (chain of one robot) in ``log``."""
    given = PlanContext.given

    def recorded(self, chain, preds):
        out = given(self, chain, preds)
        if len(chain) == 1:
            mask = self.mask(chain)
            log.append({"preds": preds.copy(), "mask": None if mask is None else mask.copy(),
                        "context": self, "extra": self.extra.copy()})  # fmt: skip
        return out

    PlanContext.given = recorded


def success_and_time(context: PlanContext, robot: int, preds: np.ndarray, mask) -> tuple:
    """``(m,)`` ``P(formed)`` and ``E[T | formed] / tau`` of each of ``robot``'s goals."""
    p = context.p
    rows = p.configurations if mask is None else p.configurations[mask]
    finish = (context.row_times if mask is None else context.row_times[mask]).max(axis=1)
    preds = preds.copy()
    preds[robot] = 1.0
    w = np.prod(preds[np.arange(preds.shape[0]), rows], axis=1)
    m = p.goals.shape[0]
    formed = np.bincount(rows[:, robot], weights=w, minlength=m)
    timed = np.bincount(rows[:, robot], weights=w * finish, minlength=m)
    with np.errstate(divide="ignore", invalid="ignore"):
        given = np.where(formed > 0, timed / formed, context.times[robot])
    return formed, given / p.tau


def _terms(context, robot, preds, mask, old, new) -> tuple[float, float]:
    formed, time = success_and_time(context, robot, preds, mask)
    success = -context.p.success_weight * np.log(np.maximum(formed, 1e-12))
    return time[old] - time[new], success[old] - success[new]


def switch_lines(record, before, now, previous) -> list[str]:
    """The lines of one switch (``record`` and ``now`` the plan, ``previous`` and
    ``before`` the robot's plan before it)."""
    r, goals = record.robot, record.goals
    old = int(np.flatnonzero(goals == previous.chosen)[0])
    new = int(np.flatnonzero(goals == record.chosen)[0])
    margin = record.G[old] - record.G[new]
    context = now["context"]
    time, success = _terms(context, r, now["preds"], now["mask"], old, new)
    head = (f"step {record.step} r{r + 1}: g{previous.chosen + 1} -> g{record.chosen + 1}, "
            f"margin {margin:.1f} nats")  # fmt: skip
    if not np.isfinite(margin):
        kept = (previous.sets.get((r,), -1), record.sets.get((r,), -1))
        return [f"{head}: the goal left is out of its set ({kept[0]} -> {kept[1]} kept)"]
    lines = [f"{head} = time {time:+.1f} + success {success:+.1f} "
             f"+ charges {margin - time - success:+.1f}"]  # fmt: skip
    carried = []
    for j in range(now["preds"].shape[0]):
        if j != r:
            back = now["preds"].copy()
            back[j] = before["preds"][j]
            carried.append((margin - sum(_terms(context, r, back, now["mask"], old, new)), j))
    gain, j = max(carried)
    a, b = before["preds"][j], now["preds"][j]
    top = [int(np.argmax(a)), int(np.argmax(b))]
    moved = float(np.hypot(*(record.positions[j] - previous.positions[j])))
    far = float(np.hypot(*(record.positions[j] - record.positions[r])))
    read = ", ".join(f"g{int(goals[g]) + 1} {before['extra'][j, g]:.1f} -> {now['extra'][j, g]:.1f}"
                     for g in dict.fromkeys(top))  # fmt: skip
    lines.append(
        f"    r{j + 1} carries {gain:.1f}: g{int(goals[top[0]]) + 1} {a[top[0]]:.2f} -> "
        f"g{int(goals[top[1]]) + 1} {b[top[1]]:.2f}; placed {moved:.1f} m from before, "
        f"{far:.1f} m away; moves read {read}"
    )
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    trial_options(ap)
    captured: list = []
    _capture(captured)
    plans = traced_trial(ap.parse_args(argv))
    last: dict = {}
    margins = []
    for record, now in zip(plans, captured, strict=True):
        previous = last.get(record.robot)
        last[record.robot] = (record, now)
        if previous is None or WAIT in (record.chosen, previous[0].chosen):
            continue
        if previous[0].chosen == record.chosen or not np.array_equal(
            previous[0].goals, record.goals
        ):
            continue
        lines = switch_lines(record, previous[1], now, previous[0])
        margins.append(lines[0])
        print("\n".join(lines))
    finite = [line for line in margins if "out of its set" not in line]
    print(f"\n{len(margins)} switches, {len(finite)} of them by the planner's scores")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
