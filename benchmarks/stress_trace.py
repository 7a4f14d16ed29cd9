"""A trace of one stress-suite trial: where each robot is, what it believes, what it saw.

Every ``--every`` steps, one line per robot: its position, the goal it is at (if any), the
goal its belief favours for itself with that belief, the configuration it acts on (the
goal number of each robot in turn), how many configurations it still keeps and how many
it models each teammate keeping (``B_ij``: where nested knowledge differs, they differ;
"believes -": it is searching, not deciding over configurations). Then the observation
events with their observers. Used for the failure traces of docs/results.md §6.

    python benchmarks/stress_trace.py specs/stress/rendezvous_hardest_5.epi third 3
"""

from __future__ import annotations

import argparse

import numpy as np

from epistemica.mission import load_mission
from epistemica.run import mission_trials
from epistemica.sim import simulate


def trace(path: str, level: str, seed: int, every: int = 10) -> str:
    trial_spec = mission_trials(load_mission(path), [level], 1, seed)[0]
    scenario = trial_spec.scenario()
    policies = trial_spec.world.policies(trial_spec.seed)
    trial = simulate(scenario, level, seed=seed, policies=policies)
    names, goals = scenario.robot_names, scenario.goal_names
    placed = zip(goals, scenario.goals, strict=True)
    lines = [
        f"{path} {level} seed {seed}: {'success' if trial.success else 'failure'} "
        f"at step {trial.steps}; ad hoc teammate: "
        + (", ".join(f"{names[r]} follows {p}" for r, p in policies.items()) or "none"),
        "goals: " + ", ".join(f"{g} ({x:.0f}, {y:.0f})" for g, (x, y) in placed),
    ]
    last = trial.trajectory.shape[0] - 1
    for step in sorted({*range(0, last, every), last}):
        lines.append(f"step {step}")
        pose = trial.trajectory[step, :, :2]
        d = np.hypot(*(pose[:, None] - scenario.goals[None]).transpose(2, 0, 1))
        for r, name in enumerate(names):
            at = goals[d[r].argmin()] if d[r].min() <= scenario.success_radius else "-"
            row = min(step, trial.goal_belief.shape[0] - 1)
            belief = trial.goal_belief[row, r]
            favoured = f"{goals[belief.argmax()]} ({belief.max():.2f})" if belief.sum() > 0 else "-"
            acts = trial.focal[row, r]
            plan = (
                "-" if (acts < 0).all() else "".join(goals[g][1:] if g >= 0 else "?" for g in acts)
            )
            models = ", ".join(
                f"{names[j]} {trial.modelled[row, r, j]}" for j in range(len(names)) if j != r
            )
            lines.append(
                f"  {name:>4} at ({pose[r, 0]:5.1f}, {pose[r, 1]:5.1f}) on {at:>4}; "
                f"believes {favoured}; acts on {plan}; keeps {trial.considered[row, r]:.0f}, "
                f"models {models}"
            )
    lines.append("events (step, name, arguments, observers):")
    for step, kind, *arguments, observers in trial.events:
        seen = ", ".join(names[i] for i in observers)
        lines.append(f"  {step:3d} {kind}{tuple(arguments)}, seen by {seen or 'nobody'}")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission")
    parser.add_argument("level")
    parser.add_argument("seed", type=int)
    parser.add_argument("--every", type=int, default=10)
    args = parser.parse_args()
    print(trace(args.mission, args.level, args.seed, args.every))


if __name__ == "__main__":
    main()
