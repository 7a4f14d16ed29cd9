"""The collaborative planning levels against the rules, closed loop, on the generated
benchmark's **tuning** split only (docs/generator.md), by team size; and the decision cost.

Each mission of the split's first ``--missions`` generator seeds runs at every level on the
first trial seed, in this one process; results go to a JSON-lines file (a rerun skips the
trials it holds). The table gives, per team-size band and overall, success and the median
and mean completion step (a failure counts at its step limit). ``--timing`` instead times
one decision per robot of the planning level on the split's 8-robot missions.

    python benchmarks/collaborative_planning.py --missions 20 --levels rules,third
    python benchmarks/collaborative_planning.py --first 100 --missions 100 --levels rules,third
    python benchmarks/collaborative_planning.py --missions 100 --robots 3-4   # small teams
    python benchmarks/collaborative_planning.py --timing --missions 40
    python benchmarks/collaborative_planning.py --trace 39:0:17   # mission 39, robot 0, step 17

**Fresh missions.** ``--first`` may go past the split's 200 missions, on along the same
tuning stream of generator seeds up to (never into) the locked split's first seed 1000000:
``--first 200 --missions 100`` runs generator seeds 200-299, missions no earlier pass has
looked at (issue 37 chose on 200-299 and confirmed on 300-399). The trial seed stays the
tuning split's first, and the output rows are the same.

    python benchmarks/collaborative_planning.py --first 200 --missions 100 --levels rules,third

``--trace`` prints one decision of a traced ``third`` trial (the split's trial seed):
the robot's particles of each teammate, the arrivals and predictions it scored with, and
every option's expected free energy (docs/results/collaborative_wrong_decision.md).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from generated_benchmark import SPLITS, family_options

from epistemica.generate import mission_text
from epistemica.mission import parse_mission
from epistemica.sim import simulate
from epistemica.sim.policies.collaborative_planning import PlanningCollaborativePolicy, explain

BANDS = ((3, 4), (5, 6), (7, 8))


def missions(count: int, policy: str = "", first: int = 0) -> list:
    """``count`` collaborative missions of the tuning stream from its ``first`` (with a
    ``policy`` line setting parameters, if given): the split's 200, or fresh ones past it,
    never reaching the locked split's generator seeds."""
    split = SPLITS["tuning"]
    locked = SPLITS["locked"].first_mission - split.first_mission
    if not 0 <= first <= first + count <= locked:
        raise SystemExit(f"--first {first} --missions {count}: must end before {locked}")
    out = []
    for k in range(first, first + count):
        seed = split.first_mission + k
        text = mission_text("collaborative", seed, family_options("collaborative"))
        if policy:
            text += f"\npolicy {policy}\n"
        out.append(parse_mission(text, f"collaborative_{seed:06d}.epi"))
    return out


def run(
    count: int, levels: list[str], path: Path, policy: str = "", first: int = 0, robots=None
) -> list[dict]:
    """Every level on every mission (trial seed: the split's first), kept in ``path``
    (a level run with a ``policy`` line is named ``level[policy]``); with ``robots``, only
    the missions of those team sizes."""
    rows = [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []
    have = {(r["mission"], r["level"]) for r in rows}
    seed = SPLITS["tuning"].trial_seeds[0]
    with path.open("a") as out:
        for mission in missions(count, policy, first):
            if robots and len(mission.robots) not in robots:
                continue
            limit = mission.scenario(seed).max_steps
            for level in levels:
                name = f"{level}[{policy}]" if policy else level
                if (mission.filename, name) in have:
                    continue
                started = time.perf_counter()
                trial = mission.trial(limit, seed, level)
                row = {
                    "mission": mission.filename,
                    "level": name,
                    "robots": len(mission.robots),
                    "success": bool(trial.success),
                    "steps": int(trial.completion_step or limit),
                    "seconds": time.perf_counter() - started,
                }
                out.write(json.dumps(row) + "\n")
                out.flush()
                rows.append(row)
    return rows


def table(rows: list[dict], levels: list[str], count: int, first: int = 0) -> list[str]:
    """Success, median and mean steps per level and team-size band."""
    names = {m.filename for m in missions(count, first=first)}
    rows = [r for r in rows if r["mission"] in names]
    lines = ["| level | robots | trials | success | median | mean |", "|---|---|---|---|---|---|"]
    for level in levels:
        for low, high in (*BANDS, (3, 8)):
            got = [r for r in rows if r["level"] == level and low <= r["robots"] <= high]
            if not got:
                continue
            steps = np.array([r["steps"] for r in got])
            won = np.mean([r["success"] for r in got])
            lines.append(
                f"| {level} | {low}-{high} | {len(got)} | {100 * won:.0f} % | "
                f"{np.median(steps):.0f} | {steps.mean():.1f} |"
            )
    return lines


def timing(count: int, level: str, steps: int, policy: str = "", robots: int = 8) -> list[str]:
    """Seconds per decision per robot of ``level`` on the split's ``robots``-robot missions,
    and each whole trial's seconds."""
    seed = SPLITS["tuning"].trial_seeds[0]
    lines = []
    for mission in missions(count, policy):
        if len(mission.robots) != robots:
            continue
        started = time.perf_counter()
        trial = mission.trial(steps, seed, level)
        whole = time.perf_counter() - started
        per = trial.decision_time / robots * 1000
        lines.append(
            f"{mission.filename}: {len(per)} steps in {whole:.1f} s, per robot median "
            f"{np.median(per):.1f} ms, 95th percentile {np.percentile(per, 95):.1f} ms, "
            f"max {per.max():.1f} ms"
        )
    return lines


def trace(mission_seed: int, robot: int, step: int, policy: str = "") -> list[str]:
    """One decision of a traced ``third`` trial of tuning-stream mission ``mission_seed``."""
    if not 0 <= mission_seed < SPLITS["locked"].first_mission:
        raise SystemExit(f"--trace {mission_seed}: the locked split is never traced")
    text = mission_text("collaborative", mission_seed, family_options("collaborative"))
    mission = parse_mission(text + (f"\npolicy {policy}\n" if policy else ""), "m.epi")
    seed = SPLITS["tuning"].trial_seeds[0]
    level = PlanningCollaborativePolicy("third", mission.parameters, trace=True)
    trial = simulate(mission.scenario(seed), level, seed=seed, parameters=mission.parameters)
    found = [d for d in level.trace if d.robot == robot and d.step == step]
    if not found:
        return [f"no decision of robot {robot} at step {step} ({trial.steps} steps)"]
    d = found[0]
    np.set_printoptions(precision=2, suppress=True, linewidth=100)
    policy_note = f", policy {policy}" if policy else ""
    knows = [f"teammate {c[1]} knows {np.flatnonzero(v).tolist()}"
             for c, v in d.sets.items() if len(c) == 2]  # fmt: skip
    return [
        f"collaborative_{mission_seed:06d}, trial seed {seed}{policy_note}: robot {robot} at "
        f"step {step} (the trial took {trial.completion_step or trial.steps} steps)",
        f"needs {list(map(int, mission.scenario(seed).needs))}",
        f"particles (never-seen starts still possible, per teammate): {d.particles.tolist()}",
        f"open tasks it knows of: {np.flatnonzero(d.sets[(robot,)]).tolist()}; " + "; ".join(knows),
        "arrivals (steps, robot x task):",
        str(d.arrivals),
        "predicted choices (robot x [tasks, explore]):",
        str(d.predictions),
        "",
        explain(d),
    ]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--missions", type=int, default=20, help="N missions of the split")
    ap.add_argument("--first", type=int, default=0, help="the index of the first (100: 100-)")
    ap.add_argument("--levels", default="rules,recruit,rules-first,oracle,third")
    ap.add_argument("--out", default="runs/collaborative-planning-tuning.jsonl")
    ap.add_argument("--policy", default="", help='parameters, e.g. "plan_repair 4"')
    ap.add_argument("--timing", action="store_true", help="time decisions instead")
    ap.add_argument("--level", default="third", help="--timing: the level timed")
    ap.add_argument("--steps", type=int, default=200, help="--timing: steps per trial")
    ap.add_argument("--robots", default="", help="team sizes run, e.g. 3-4 (--timing: one, 8)")
    ap.add_argument("--trace", default="", help="MISSION:ROBOT:STEP, one traced decision")
    args = ap.parse_args(argv)
    if args.trace:
        mission_seed, robot, step = map(int, args.trace.split(":"))
        print("\n".join(trace(mission_seed, robot, step, args.policy)))
        return 0
    if args.timing:
        robots = int(args.robots or 8)
        print("\n".join(timing(args.missions, args.level, args.steps, args.policy, robots)))
        return 0
    levels = [name.strip() for name in args.levels.split(",")]
    path = Path(args.out)
    path.parent.mkdir(parents=True, exist_ok=True)
    low, _, high = args.robots.partition("-")
    team = set(range(int(low), int(high or low) + 1)) if low else None
    rows = run(args.missions, levels, path, args.policy, args.first, team)
    named = [f"{level}[{args.policy}]" if args.policy else level for level in levels]
    print("\n".join(table(rows, named, args.missions, args.first)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
