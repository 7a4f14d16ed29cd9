"""One planning trial, traced: what a robot predicted of each teammate and how it scored its
options at each decision, as Markdown.

Runs one trial of a mission at a planning level inside
:func:`epistemica.sim.policies.planning.recording_plans`, then prints the outcome, how
often each robot changed its goal, and, for one robot over a range of steps, every
decision: the options (head for a goal, or wait) with their expected free energy ``G``
(nats, lower is better), the goal chosen, where the robot placed each teammate and the
goal distribution it predicted for it (its top three goals), whether it had ever seen
that teammate, the sizes of the nested sets it planned over, and its belief's mode.
Robots and goals are named as in mission files (``r1``, ``g1``: 1-based).

Usage::

    python benchmarks/planning_trace.py specs/stress/allocation_hardest_8.epi --seed 20009 \\
        --level third --set plan_unseen=false --robot r2 --steps 35:40

``docs/results/planning_wrong_decision.md`` is this script's output at a decision that
went wrong, with the fix it led to.
"""

from __future__ import annotations

import argparse
import re
from collections import Counter
from pathlib import Path

import numpy as np

from epistemica.aif.teammates import TYPES
from epistemica.mission import parse_mission
from epistemica.sim.policies.planning import WAIT, PlanRecord, recording_plans


def _goal(index: int) -> str:
    return "wait" if index == WAIT else f"g{index + 1}"


def _step_limit(path: Path) -> int:
    found = re.search(r"^simulate .*\bsteps (\d+)", path.read_text(), re.MULTILINE)
    return int(found.group(1)) if found else 60


def decision_table(record: PlanRecord) -> list[str]:
    """Markdown lines of one decision: its options and its predictions of each robot."""
    lines = [
        f"**step {record.step}, r{record.robot + 1} heads for {_goal(record.chosen)}**",
        "",
        "| option | G (nats) |",
        "|---|---:|",
    ]
    order = np.argsort(np.where(np.isfinite(record.G), record.G, np.inf), kind="stable")
    for local in order:
        value = record.G[local]
        shown = f"{value:.2f}" if np.isfinite(value) else "excluded"
        mark = " (chosen)" if int(record.goals[local]) == record.chosen else ""
        lines.append(f"| {_goal(int(record.goals[local]))}{mark} | {shown} |")
    if np.isfinite(record.wait):
        lines.append(f"| wait | {record.wait:.2f} |")
    typing = record.types is not None
    header = "| robot | placed at | ever seen | predicted goals (top 3) |"
    lines += ["", header + (f" type posterior ({' / '.join(TYPES)}) |" if typing else "")]
    lines.append("|---|---|---|---|" + ("---|" if typing else ""))
    for j, row in enumerate(record.predictions):
        top = np.argsort(-row, kind="stable")[:3]
        guess = ", ".join(f"{_goal(int(record.goals[g]))} {row[g]:.2f}" for g in top)
        x, y = record.positions[j]
        who = f"r{j + 1}" + (" (itself)" if j == record.robot else "")
        seen = "yes" if record.seen[j] else "no"
        line = f"| {who} | ({x:.1f}, {y:.1f}) | {seen} | {guess} |"
        if typing:
            held = " (typed: held to its goal)" if record.typed[j] else ""
            line += " " + " / ".join(f"{p:.2f}" for p in record.types[j]) + held + " |"
        lines.append(line)
    sizes = Counter(len(chain) for chain, size in record.sets.items() if size > 0)
    empty = sum(1 for size in record.sets.values() if size == 0)
    lines += [
        "",
        f"Nested sets: {dict(sorted(sizes.items()))} non-empty by chain length, {empty} empty "
        f"(an empty set restricts nothing); belief mode {record.belief.max():.3f} over "
        f"{record.belief.size} configurations.",
        "",
    ]
    return lines


def trial_options(ap: argparse.ArgumentParser) -> None:
    """The options that choose one trial: mission file, seed, level, parameter changes."""
    ap.add_argument("mission", type=Path)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--level", default="third")
    ap.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE",
        help="a policy parameter, as a mission file's `policy NAME VALUE` line",
    )  # fmt: skip


def traced_trial(args: argparse.Namespace) -> list[PlanRecord]:
    """Run the trial ``args`` chooses (:func:`trial_options`) recording its plans; print
    its outcome line and return the plans."""
    text = args.mission.read_text()
    text += "".join(f"\npolicy {item.replace('=', ' ', 1)}" for item in args.set) + "\n"
    mission = parse_mission(text, str(args.mission))
    with recording_plans() as plans:
        trial = mission.trial(_step_limit(args.mission), args.seed, args.level)
    outcome = "succeeded" if trial.success else "failed"
    print(f"# {args.mission.stem}, seed {args.seed}, `{args.level}`: {outcome} in {trial.steps}")
    return plans


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    trial_options(ap)
    ap.add_argument("--robot", default="r1", help="the robot whose decisions are printed")
    ap.add_argument("--steps", default="0:5", help="first:last step printed (inclusive)")
    args = ap.parse_args(argv)
    robot = int(args.robot.lstrip("r")) - 1
    first, last = (int(part) for part in args.steps.split(":"))
    plans = traced_trial(args)
    changes: Counter = Counter()
    heading: dict[int, int] = {}
    for record in plans:
        if heading.get(record.robot) not in (None, record.chosen):
            changes[record.robot] += 1
        heading[record.robot] = record.chosen
    print()
    print("Goal changes per robot: " + ", ".join(
        f"r{r + 1} {changes[r]}" for r in sorted(heading)))  # fmt: skip
    print()
    for record in plans:
        if record.robot == robot and first <= record.step <= last:
            print("\n".join(decision_table(record)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
