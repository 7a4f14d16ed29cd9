"""One row per mechanism of the active levels: what removing it costs (issue 19 §5).

For each mission file, runs the full level (default ``rules-third``; ``third`` adds the
planner's own rules and terms) and, for each mechanism,
the same level with that mechanism removed, on the same seeds. Prints success of the full
level, then per mechanism and mission the change in success (points) and the mean paired
change in completion steps over the trials both solve, when the mechanism is removed.

Finished trials are appended to a JSON-lines file (``--cache``), so an interrupted run
resumes where it stopped; a cached trial is reused only for the same file, level and seed.

    python benchmarks/ablation_table.py specs/stress/rendezvous_radius_5.epi \\
        specs/nested/private_goal_3.epi --seeds 0-99 --workers 1 --cache ablation.jsonl
"""

from __future__ import annotations

import argparse
import json
import statistics
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from level_study import _seeds, run_one, wilson

from epistemica.sim.policies.levels import make_policy

#: Mechanism -> the parameter changes that remove it (fields of ActiveParameters or
#: controller arguments, in level_study's ``name=value;...`` form).
MECHANISMS = {
    "expected free energy": "free_energy=false",
    "evidence from teammates' motion": "eta=1e12;eta_bearing=1e12",
    "nested sets": "nested=false",
    "anticipation": "anticipate=false",
    "teammate models": "teammate_models=false",
    "common view": "common_view=false",
    "group search": "search=false",
    "anchors": "anchor_check=0",
    "short wait when unaware": "unaware_wait=15",
    "pruning by events": "pruning=false",
    "recency revision": "revision=primacy",
}

#: The planning levels' own rules and terms (aif.md §6g), removed the same way; listed by
#: default when the level plans (``third``, ``second``, ...), where they act.
PLANNER_MECHANISMS = {
    "planner's evidence of teammates' goals": "plan_evidence=1e12;plan_sigma=1e12",
    "meeting of searching groups": "plan_meet=false",
    "an anchor outranks a find": "plan_anchor=false",
    "searchers look where teammates were last seen": "plan_sighted=false",
    "joining teammates settled at a goal not known": "plan_join=0",
    "goals a teammate was not shown": "plan_few=false",
    "contested goals priced by arrival": "plan_claim=0",
    "never-seen teammates predicted blind": "plan_blind=false",
    "sightings' stated noise": "plan_noise=0",
    "teammate types": "plan_types=0",
    "success weight": "plan_success=0",
    "commitment": "plan_commitment=0",
    "convention tie-break": "plan_convention=0",
}


def _load(cache: Path | None) -> dict:
    done: dict = {}
    if cache and cache.exists():
        for line in cache.read_text().splitlines():
            if line.strip():
                row = json.loads(line)
                done[(row["mission"], row["level"], row["seed"])] = (row["success"], row["steps"])
    return done


def run_all(jobs: list, workers: int, cache: Path | None) -> dict:
    """``(mission, level, seed) -> (success, steps)``, new trials appended to ``cache``."""
    done = _load(cache)
    todo = [job for job in jobs if job not in done]
    with ProcessPoolExecutor(workers) as pool:
        for path, spec, seed, success, steps in pool.map(run_one, todo, chunksize=2):
            done[(path, spec, seed)] = (success, steps)
            if cache:
                row = dict(mission=path, level=spec, seed=seed, success=success, steps=steps)
                with cache.open("a") as out:
                    out.write(json.dumps(row) + "\n")
    return done


def cell(full: dict, ablated: dict) -> str:
    """Success change in points and paired step change when the mechanism is removed."""
    seeds = sorted(full)
    points = 100 * (sum(ablated[s][0] for s in seeds) - sum(full[s][0] for s in seeds))
    both = [s for s in seeds if full[s][0] and ablated[s][0]]
    points /= len(seeds)
    if not both:
        return f"{points:+.0f}"
    change = statistics.mean((ablated[s][1] - full[s][1]) / full[s][1] for s in both)
    return f"{points:+.0f}, {100 * change:+.1f} %"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="+")
    parser.add_argument("--seeds", default="0-99", help="first-last (inclusive)")
    parser.add_argument("--level", default="rules-third")
    parser.add_argument("--mechanisms", help="comma-separated names (default: all)")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--cache", type=Path, help="JSON-lines file of finished trials")
    args = parser.parse_args()
    seeds = _seeds(args.seeds)
    known = MECHANISMS | PLANNER_MECHANISMS
    plans = make_policy(args.level.partition(":")[0]).parameters.planning
    default = list(known) if plans else list(MECHANISMS)
    names = args.mechanisms.split(",") if args.mechanisms else default
    unknown = [n for n in names if n not in known]
    if unknown:
        parser.error(f"unknown mechanism {unknown[0]!r}; known: {', '.join(known)}")
    specs = [args.level] + [f"{args.level}:{known[n]}" for n in names]
    jobs = [(str(p), spec, s) for p in args.missions for spec in specs for s in seeds]
    done = run_all(jobs, args.workers, args.cache)

    def results(path, spec):
        return {s: done[(str(path), spec, s)] for s in seeds}

    def pooled(spec):
        return {(p, s): done[(str(p), spec, s)] for p in args.missions for s in seeds}

    stems = [Path(p).stem for p in args.missions] + [f"all {len(args.missions)} pooled"]
    print(f"seeds {args.seeds}; level {args.level}\n")
    print("| mechanism removed | " + " | ".join(stems) + " |")
    print("|---|" + "---|" * len(stems))
    row = []
    for full in [results(p, args.level) for p in args.missions] + [pooled(args.level)]:
        k = sum(s for s, _ in full.values())
        low, high = wilson(k, len(full))
        steps = statistics.mean([t for s, t in full.values() if s] or [0])
        row.append(f"{100 * k / len(full):.0f} % [{low:.0f}, {high:.0f}], {steps:.1f} steps")
    print(f"| none ({args.level}) | " + " | ".join(row) + " |")
    for name, spec in zip(names, specs[1:], strict=True):
        cells = [cell(results(p, args.level), results(p, spec)) for p in args.missions]
        cells.append(cell(pooled(args.level), pooled(spec)))
        print(f"| {name} | " + " | ".join(cells) + " |")
    print(
        "\ncells: change in success (points) and mean paired change in steps (trials both "
        "solve) when the mechanism is removed"
    )


if __name__ == "__main__":
    main()
