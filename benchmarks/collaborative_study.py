"""Collaborative tasks found while exploring: the levels on the same seeds, per team size.

For each mission file (specs/collaborative/tasks_3.epi, tasks_5.epi, tasks_8.epi) and
level, runs the trials of the given seeds and prints success (with a 95 % Wilson
interval), the mean completion step of the successes, and the paired change of ``rules``'s
completion step against rules-first, rules-shared and the oracle on the trials both solve
(the two mean completion steps over those trials, and their relative change). A level may carry
parameter changes after a colon, as in benchmarks/level_study.py:
``rules:fetch_memory=40;seek=false`` (fields of
:class:`epistemica.sim.policies.collaborative_levels.CollaborativeParameters`).

    python benchmarks/collaborative_study.py specs/collaborative/tasks_*.epi --seeds 0-99
    python benchmarks/collaborative_study.py specs/collaborative/tasks_5.epi \\
        --seeds 1000-1029 --levels rules-first,rules,rules:seek=false
    python benchmarks/collaborative_study.py --speed      # one 5-robot 200-step trial
    python benchmarks/collaborative_study.py specs/collaborative/tasks_*.epi \\
        --prediction-error --seeds 0-99   # how far rules predicts unseen teammates
    python benchmarks/collaborative_study.py specs/collaborative/tasks_5.epi \
        --time-use --seeds 1000-1049 --levels rules-first,rules,oracle-events  # robot-steps by use
    python benchmarks/collaborative_study.py specs/collaborative/tasks_8.epi \
        --trace rules --seeds 17                          # one trial, step by step
    python benchmarks/collaborative_study.py specs/collaborative/tasks_3.epi \
        --trace "rules:stale_after=0" --seeds 1010        # ... with parameter changes
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from level_study import _level, _seeds, print_table, run_table

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.policies.collaborative_levels import CollaborativePolicy

LEVELS = "convention,rules-first,rules-shared,rules,oracle"
PAIRS = ("rules-first", "rules-shared", "oracle")


def run_one(job: tuple[str, str, int]) -> tuple[str, str, int, bool, int]:
    path, spec, seed = job
    mission = load_mission(path)
    level, changes = _level(spec)
    parameters = mission.parameters.replace(**changes) if changes else mission.parameters
    trial = simulate(mission.scenario(seed), level, seed, parameters=parameters)
    return path, spec, seed, bool(trial.success), int(trial.steps)


def speed(path: str, repeats: int = 5) -> None:
    """Median wall time of a 5-robot trial run for exactly 200 steps, per level."""
    mission = load_mission(path)
    for level in LEVELS.split(","):
        times = []
        for seed in range(repeats):
            scenario = mission.scenario(seed)
            # tasks out of reach, so the trial runs its 200 steps whatever the level does
            scenario = scenario.replace(
                max_steps=200, needs=(len(mission.robots),) * len(scenario.needs)
            )
            started = time.perf_counter()
            trial = simulate(scenario, level, seed, parameters=mission.parameters)
            times.append(time.perf_counter() - started)
        print(f"  {level}: median {statistics.median(times):.2f} s ({trial.steps} steps)")


def trace(path: str, level: str, seed: int, every: int = 10) -> None:
    """Every ``every`` steps: each robot's place, what it steers to, the tasks it knows
    and, per task, the teammates it knows know it; then the events with their observers."""
    mission = load_mission(path)
    scenario = mission.scenario(seed)
    level, changes = _level(level)
    parameters = mission.parameters.replace(**changes) if changes else mission.parameters
    trial = simulate(scenario, level, seed, parameters=parameters)
    names, tasks = scenario.robot_names, scenario.task_names
    print(f"{Path(path).stem} {level} seed {seed}: success {trial.success}, {trial.steps} steps")
    print("tasks: " + ", ".join(
        f"{t} at ({x:.0f}, {y:.0f}) needs {k}, done at {d}"
        for t, (x, y), k, d in zip(tasks, scenario.tasks, scenario.needs, trial.tasks_done,
                                   strict=True)))  # fmt: skip
    steer = {-1: "explore", -2: "fetch"}
    for step in range(0, trial.steps, every):
        print(f"step {step}")
        for i, name in enumerate(names):
            x, y = trial.trajectory[step, i, :2]
            target = int(trial.steer_to[step, i])
            known = [tasks[t] for t in range(len(tasks)) if trial.knows[step, i, t]]
            print(f"  {name} ({x:5.1f}, {y:5.1f}) {steer.get(target, tasks[target]):>8}  "
                  f"knows {', '.join(known) or '-'}")  # fmt: skip
    k = trial.knowledge
    print("at the end, robot: task <- teammates it knows know it")
    for i, name in enumerate(names):
        parts = []
        for t, task in enumerate(tasks):
            who = [names[j] for j in range(len(names)) if j != i and k.knows_goals((i, j))[t]]
            parts.append(f"{task} <- {', '.join(who) or '-'}")
        print(f"  {name}: " + "; ".join(parts))
    print("events (step, name, arguments, observers):")
    for step, name, arguments, observers in trial.events:
        print(f"  {step} {name}({', '.join(arguments)}) seen by "
              f"{', '.join(names[o] for o in observers)}")  # fmt: skip


USES = (
    "exploring, knowing no open task",
    "exploring, knowing one",
    "fetching",
    "going to a task",
    "waiting at a task",
)


def time_use(paths: list[str], levels: list[str], seeds: list[int]) -> None:
    """Mean robot-steps per trial by what the robot does: exploring while it knows of no
    open task (news it lacks), exploring while it knows of one, fetching a teammate, going
    to a task, waiting at one (within the completion radius of the task it steers to)."""
    for path in paths:
        mission = load_mission(path)
        print(f"{Path(path).stem}, robot-steps per trial (seeds {seeds[0]}-{seeds[-1]}):")
        print("| level | steps | " + " | ".join(USES) + " |")
        print("|---|---|" + "---|" * len(USES))
        for spec in levels:
            level, changes = _level(spec)
            parameters = mission.parameters.replace(**changes) if changes else mission.parameters
            counts, steps = np.zeros(len(USES)), 0
            for seed in seeds:
                scenario = mission.scenario(seed)
                trial = simulate(scenario, level, seed, parameters=parameters)
                counts += _uses(trial, scenario)
                steps += trial.steps
            cells = " | ".join(f"{c / len(seeds):.1f}" for c in counts)
            print(f"| {spec} | {steps / len(seeds):.1f} | {cells} |")


def _uses(trial, scenario) -> np.ndarray:
    """Robot-steps of one trial per entry of :data:`USES`."""
    target = trial.steer_to  # (steps, n)
    step = np.arange(trial.steps)[:, None]
    done = trial.tasks_done
    open_then = (done[None] < 0) | (done[None] > step)  # (steps, m)
    knows_open = (trial.knows & open_then[:, None, :]).any(axis=2)
    heading = target >= 0
    goal = scenario.tasks[np.where(heading, target, 0)]
    at_task = np.hypot(*(trial.trajectory[:-1, :, :2] - goal).transpose(2, 0, 1))
    waiting = heading & (at_task <= scenario.completion_radius)
    exploring = target == -1
    return np.array([
        (exploring & ~knows_open).sum(), (exploring & knows_open).sum(),
        (target == -2).sum(), (heading & ~waiting).sum(), waiting.sum(),
    ])  # fmt: skip


def prediction_error(paths: list[str], seeds: list[int]) -> None:
    """Median distance from where ``rules``' robots predict each teammate they do not see
    to where it is, every step, against the mean distance of two random points in the
    workspace (a wrapper around :meth:`CollaborativePolicy.decide` records it)."""
    decide, gaps = CollaborativePolicy.decide, []

    def recording(policy, view):
        for i, j in zip(*np.nonzero(view.last_seen != view.step), strict=True):
            if i != j:
                since = view.step - max(view.last_seen[i, j], 0)
                where = policy.predicted(view, i, j) - view.poses[j, :2]
                gaps.append((since, float(np.hypot(*where))))
        return decide(policy, view)

    CollaborativePolicy.decide = recording
    try:
        for path in paths:
            mission, gaps[:] = load_mission(path), []
            for seed in seeds:
                simulate(mission.scenario(seed), "rules", seed, parameters=mission.parameters)
            since, gap = np.array(gaps).T
            random = 0.5214 * mission.scenario(seeds[0]).workspace  # two uniform points
            print(
                f"{Path(path).stem}: median {np.median(gap):.1f} m (seen in the last 40 "
                f"steps {np.median(gap[since <= 40]):.1f} m, longer ago "
                f"{np.median(gap[since > 40]):.1f} m); two random points {random:.1f} m"
            )
    finally:
        CollaborativePolicy.decide = decide


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="*")
    parser.add_argument("--seeds", default="0-99", help="first-last (inclusive)")
    parser.add_argument("--levels", default=LEVELS)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--speed", action="store_true", help="time 5-robot 200-step trials")
    parser.add_argument(
        "--trace", metavar="LEVEL", help="print one trial (the first seed); LEVEL may carry changes"
    )
    parser.add_argument(
        "--prediction-error", action="store_true", help="how far rules predicts unseen teammates"
    )
    parser.add_argument(
        "--time-use", action="store_true", help="robot-steps per trial by what robots do"
    )
    args = parser.parse_args()
    if args.prediction_error:
        prediction_error(args.missions, _seeds(args.seeds))
        return
    if args.time_use:
        time_use(args.missions, args.levels.split(","), _seeds(args.seeds))
        return
    if args.trace:
        trace(args.missions[0], args.trace, _seeds(args.seeds)[0])
        return
    if args.speed:
        speed(args.missions[0] if args.missions else "specs/collaborative/tasks_5.epi")
        return
    levels = args.levels.split(",")
    seeds = _seeds(args.seeds)
    table = run_table(run_one, args.missions, levels, seeds, args.workers)
    print(f"seeds {args.seeds}\n")
    print_table(table, args.missions, levels, "")
    focus = next((lv for lv in levels if lv == "rules" or lv.startswith("rules:")), None)
    if focus is None:
        return
    print(f"\npaired change of {focus}'s completion step (trials both solve):")
    for path in args.missions:
        parts = []
        for other in [lv for lv in levels if lv in PAIRS or (lv != focus and ":" in lv)]:
            a, b = table[(path, other)], table[(path, focus)]
            both = [s for s in seeds if a[s][0] and b[s][0]]
            if both:
                mine = statistics.mean(b[s][1] for s in both)
                theirs = statistics.mean(a[s][1] for s in both)
                relative = (mine - theirs) / theirs
                parts.append(
                    f"vs {other}: {mine:.1f} against {theirs:.1f} steps, "
                    f"{100 * relative:+.1f} % over {len(both)}"
                )
        print(f"  {Path(path).stem}: " + "; ".join(parts))


if __name__ == "__main__":
    main()
