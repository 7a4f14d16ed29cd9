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
from epistemica.mission import load_mission
from epistemica.output_files import check_output, write_output
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.figures import animate_trial, plot_trial
from epistemica.sim.study.frames import frame_type
from epistemica.sim.study.trace import trial_trace

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
    trace = trial_trace(scenario, trial)
    if args.json:
        record = {
            "mission": scenario.kind.name,
            "robots": len(trace["robots"]),
            "goals": len(trace["goals"]),
            "sensors": list(trace["sensors"]),
            "observation": getattr(scenario, "observation", None),
            "sensing_range": trace["sensing_range"],
            **trial.summary(),
        }
        print_json("simulate", record)
    else:
        print(_describe(scenario, trial, trace))
    return 0 if trial.success else 1


def _trial(args: argparse.Namespace):
    """The scenario and trial asked for: ``--mission`` a built-in mission (the published
    protocol) or a mission file (its layout and teammates at ``--seed``, its last level by
    default)."""
    if args.mission.endswith(".epi") or os.path.isfile(args.mission):
        mission = load_mission(args.mission)
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


def _describe(scenario, trial, trace: dict) -> str:
    """The outcome and, per robot, its sensor, level, what it did last (the kind's frame
    says: the goal it headed for, the task it steered to) and where it ended."""
    verdict = (
        f"succeeded at step {trial.steps}"
        if trial.success
        else f"failed within {trial.steps} steps"
    )
    places = "tasks" if scenario.kind.tasks else "goals"
    robots = trace["robots"]
    lines = [
        f"{scenario.kind.name} with {len(robots)} robots and {len(trace['goals'])} {places}, "
        f"seed {trial.seed}: {verdict}"
    ]
    frame = frame_type(trace)
    width = max(len(name) for name in robots)
    for i, robot in enumerate(robots):
        x, y = trial.trajectory[-1, i, :2]
        lines.append(
            f"  {robot:<{width}}  {trace['sensors'][i]:<7}  {trial.policies[i]:<18}  "
            f"{frame.status(trace, i):<16}  at ({x:.1f}, {y:.1f})"
        )
    if trial.completion_step is not None:
        lines.append(f"  all tasks done at step {trial.completion_step}")
    return "\n".join(lines)
