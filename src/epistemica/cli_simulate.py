"""``epistemica simulate``: one trial of the published protocol, as text, JSON or pictures.

Exit status: 0 when the mission succeeded, 1 when it failed (a claim about the trial that
turned out false), 2 on bad input.
"""

from __future__ import annotations

import argparse
import json

from epistemica.cli_options import add_scenario_options, scenario_options

__all__ = ["add_command"]

_EXAMPLES = """\
examples:
  epistemica simulate --mission allocation --robots 4 --seed 2 --reasoning third
  epistemica simulate --mission rendezvous --robots 3 --goals 4 --reasoning convention --json
  epistemica simulate --mission allocation --robots 5 --png trial.png --gif trial.gif
  epistemica simulate --mission rendezvous --robots 3 --observation honest --sensing-range 10

exit status: 0 the mission succeeded, 1 it failed, 2 bad input
"""


def add_command(commands) -> None:
    """Register ``simulate`` on an argparse subparsers object."""
    cmd = commands.add_parser(
        "simulate",
        help="simulate one trial of a multi-robot mission",
        description="Simulate one trial of the published protocol (Scenario.paper) at a "
        "reasoning level and report its outcome; optionally draw it.",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    cmd.add_argument("--mission", default="rendezvous", help="rendezvous, allocation, multitask")
    cmd.add_argument("--robots", type=int, default=3, help="team size (default 3)")
    cmd.add_argument(
        "--goals", type=int, default=None, help="goals (default: as many as robots; multitask 20)"
    )
    cmd.add_argument("--seed", type=int, default=0, help="trial seed (default 0)")
    cmd.add_argument(
        "--reasoning",
        default="third",
        help="zero, convention, first, second, third, paper-first, paper-higher, "
        "paper-higher-fixed (default third)",
    )
    add_scenario_options(cmd)
    cmd.add_argument("--json", action="store_true", help="print a JSON object")
    cmd.add_argument("--png", metavar="FILE", help="write the trajectories as a PNG")
    cmd.add_argument("--gif", metavar="FILE", help="write an animation with the beliefs")
    cmd.set_defaults(handler=_simulate)


def _simulate(args: argparse.Namespace) -> int:
    from epistemica.sim import Scenario, simulate

    options = scenario_options(args)
    scenario = Scenario.paper(args.mission, args.robots, args.goals, args.seed, **options)
    trial = simulate(scenario, args.reasoning, seed=args.seed)
    if args.png:
        from epistemica.sim.figures import plot_trial

        plot_trial(scenario, trial, args.png)
    if args.gif:
        from epistemica.sim.figures import animate_trial

        animate_trial(scenario, trial, args.gif)
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
        print(json.dumps(record, indent=2))
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
