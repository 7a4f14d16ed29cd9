"""``epistemica simulate``: one trial of the published protocol, as text, JSON or pictures.

Exit status: 0 when the mission succeeded, 1 when it failed (a claim about the trial that
turned out false), 2 on bad input.
"""

from __future__ import annotations

import argparse
from functools import partial

from epistemica.cli.json_output import print_json
from epistemica.cli.options import scenario_options
from epistemica.output_files import check_output, write_output
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.figures import animate_trial, plot_trial

__all__ = ["run_simulate"]


def run_simulate(args: argparse.Namespace) -> int:

    for flag, path in (("--png", args.png), ("--gif", args.gif)):
        if path:
            check_output(path, force=args.force, flag=flag)  # before the trial, not after it
    options = scenario_options(args)
    scenario = Scenario.paper(args.mission, args.robots, args.goals, args.seed, **options)
    trial = simulate(scenario, args.reasoning, seed=args.seed)
    if args.png:
        write_output(args.png, partial(plot_trial, scenario, trial))
    if args.gif:
        write_output(args.gif, partial(animate_trial, scenario, trial))
    if args.json:
        record = {
            "mission": scenario.mission,
            "robots": scenario.n_robots,
            "goals": scenario.n_goals,
            "sensors": list(scenario.sensors),
            "observation": scenario.observation,
            "sensing_range": scenario.sensing_range,
            **trial.summary(),
        }
        print_json("simulate", record)
    else:
        print(_describe(scenario, trial))
    return 0 if trial.success else 1


def _describe(scenario, trial) -> str:
    verdict = (
        f"succeeded at step {trial.steps}"
        if trial.success
        else (f"failed within {trial.steps} steps")
    )
    lines = [
        f"{scenario.mission} with {scenario.n_robots} robots and {scenario.n_goals} "
        f"goals, seed {trial.seed}: {verdict}"
    ]
    last = trial.focal[-1] if trial.steps else None
    for i in range(scenario.n_robots):
        goal = "-" if last is None or last[i, i] < 0 else f"g{last[i, i]}"
        x, y = trial.trajectory[-1, i, :2]
        lines.append(
            f"  r{i}  {scenario.sensors[i]:<7}  {trial.policies[i]:<18}  "
            f"heading for {goal:<4}  at ({x:.1f}, {y:.1f})"
        )
    if trial.completion_step is not None:
        lines.append(f"  all tasks done at step {trial.completion_step}")
    return "\n".join(lines)
