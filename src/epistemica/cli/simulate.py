"""``epistemica simulate``: one trial of the published protocol (or of a mission file), as
text, JSON or pictures.

Exit status: 0 when the mission succeeded, 1 when it failed (a claim about the trial that
turned out false), 2 on bad input.
"""

from __future__ import annotations

import argparse
import os
from functools import partial

from epistemica.cli.json_output import print_json
from epistemica.cli.options import scenario_options
from epistemica.del_.errors import InvalidArgumentError
from epistemica.mission import load_mission
from epistemica.output_files import check_output, write_output
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.figures import animate_trial, plot_trial

__all__ = ["run_simulate"]


def run_simulate(args: argparse.Namespace) -> int:

    for flag, path in (("--png", args.png), ("--gif", args.gif)):
        if path:
            check_output(path, force=args.force, flag=flag)  # before the trial, not after it
    scenario, trial = _trial(args)
    say = print if not args.json else (lambda *a: None)
    if args.png:
        write_output(args.png, partial(plot_trial, scenario, trial))
        say(f"figure: {args.png}")
    if args.gif:
        frames = []
        write_output(args.gif, lambda out: frames.append(animate_trial(scenario, trial, out)))
        say(f"animation: {args.gif} ({frames[0]} frames; drawing them takes longer than the trial)")
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


def _trial(args: argparse.Namespace):
    """The scenario and trial asked for: ``--mission`` a built-in mission (the published
    protocol) or a mission file (its layout and teammates at ``--seed``, its last level by
    default)."""
    if args.mission.endswith(".epi") or os.path.isfile(args.mission):
        mission = load_mission(args.mission)
        if mission.kind.joint:  # its pictures are its study's (run)
            raise InvalidArgumentError(
                f"{args.mission}: simulate draws goal and multitask missions",
                hint=f"run its study with 'epistemica run {args.mission}'",
            )
        level = args.reasoning or mission.study.levels[-1]
        scenario = mission.scenario(args.seed)
        trial = simulate(
            scenario,
            level,
            seed=args.seed,
            policies=mission.policies(args.seed),
            parameters=mission.parameters,
        )
        return scenario, trial
    options = scenario_options(args)
    scenario = Scenario.paper(args.mission, args.robots, args.goals, args.seed, **options)
    return scenario, simulate(scenario, args.reasoning or "third", seed=args.seed)


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
    width = max(len(name) for name in scenario.robot_names)
    for i, robot in enumerate(scenario.robot_names):
        goal = "-" if last is None or last[i, i] < 0 else scenario.goal_names[last[i, i]]
        x, y = trial.trajectory[-1, i, :2]
        lines.append(
            f"  {robot:<{width}}  {scenario.sensors[i]:<7}  {trial.policies[i]:<18}  "
            f"heading for {goal:<4}  at ({x:.1f}, {y:.1f})"
        )
    if trial.completion_step is not None:
        lines.append(f"  all tasks done at step {trial.completion_step}")
    return "\n".join(lines)
