"""Fingerprints of a fixed sample of simulated trials, to show a refactor changed nothing.

Each trial (mission file, level, seed) is summarised by its outcome and a hash of its
record (trajectory, focal configurations, configuration-set sizes, and each event's step,
kind and observers). Write the
fingerprints of one version, then compare another version against them:

    python benchmarks/trial_fingerprints.py --write before.jsonl
    python benchmarks/trial_fingerprints.py --compare before.jsonl
    python benchmarks/trial_fingerprints.py --compare old.jsonl --before-switch  # renamed

``--sample`` chooses the set: ``stress`` (every stress-suite variant at 3 and 5 robots, four
levels of the rules, seeds 0-1, and the 10-robot radius and hardest cells at seed 0), ``shipped``
(every mission file under specs/, its own levels, seeds 0-2), ``nested`` (every file of
specs/nested/, its own levels, seeds 0-9) or ``collaborative`` (specs/collaborative/, every
collaborative level, seeds 0-99).

The ``nested`` and ``collaborative`` samples hash what the stored trace of the trial says
(success, steps, every pose, each event's step, name and observers, and for collaborative
trials when each task was done and where each robot steered), so that they compare across
versions whose in-memory trial records differ.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from pathlib import Path

import numpy as np

from epistemica.mission import load_mission
from epistemica.run import mission_trials
from epistemica.sim.study.sweep import run_trial
from epistemica.sim.study.trace import decode

ROOT = Path(__file__).resolve().parents[1]
STRESS_LEVELS = ("convention", "rules-first", "rules-third", "rules-third-shared")


COLLABORATIVE_LEVELS = (
    "convention",
    "rules-first",
    "rules-shared",
    "rules",
    "oracle",
    "oracle-events",
)
#: ``--before-switch``: the level names of fingerprints written before the level switch
#: (issue 37) -> today's names of the same policies (goal kinds; collaborative).
OLD_NAMES = {
    "first": "rules-first",
    "second": "rules-second",
    "third": "rules-third",
    **{f"{o}-{a}": f"rules-{o}-{a}" for o in ("first", "second", "third")
       for a in ("shared", "unpruned")},
    **{f"plan-{name}": name for name in ("first", "second", "third", "third-shared")},
    "plan-third-wait": "third-wait",
}  # fmt: skip
OLD_JOINT_NAMES = {
    "first": "rules-first",
    "third": "rules",
    "third-shared": "rules-shared",
    **{f"plan-{name}": name for name in ("first", "second", "third", "third-shared")},
    "plan-third-priormode": "third-priormode",
}


def _cases(sample: str) -> list[tuple[Path, str, int]]:
    stress = ROOT / "specs" / "stress"
    if sample == "nested":
        files = sorted(ROOT.glob("specs/nested/*.epi"))
        return [(f, level, seed) for f in files for level in _levels(f) for seed in range(10)]
    if sample == "collaborative":
        files = sorted(ROOT.glob("specs/collaborative/*.epi"))
        return [(f, lv, seed) for f in files for lv in COLLABORATIVE_LEVELS for seed in range(100)]
    if sample == "shipped":
        files = sorted(ROOT.glob("specs/*.epi"))
        return [(f, level, seed) for f in files for level in _levels(f) for seed in range(3)]
    cases = [
        (path, level, seed)
        for path in sorted(stress.glob("*_[35].epi"))
        for level in STRESS_LEVELS
        for seed in (0, 1)
    ]
    for name in ("allocation_radius_10", "rendezvous_hardest_10"):
        cases += [(stress / f"{name}.epi", level, 0) for level in ("convention", "rules-third")]
    return cases


def _levels(path: Path) -> tuple[str, ...]:
    return load_mission(path).study.levels


def _key(path: Path, level: str, seed: int) -> str:
    return f"{path.stem}/{level}/{seed}"


def renamed(key: str, names: dict[str, str]) -> str:
    """A stored trial's key with its level renamed by ``names`` (the rest kept).

    >>> renamed("tasks_3/third/4", OLD_JOINT_NAMES), renamed("moved_3/third-shared/0", OLD_NAMES)
    ('tasks_3/rules/4', 'moved_3/rules-third-shared/0')
    """
    stem, level, seed = key.split("/")
    return f"{stem}/{names.get(level, level)}/{seed}"


def trace_fingerprint(path: Path, level: str, seed: int) -> dict:
    """The outcome of one trial and a hash of its stored trace's observable record."""
    spec = mission_trials(load_mission(path), [level], 1, seed)[0]
    trace = decode(run_trial(spec)["trace"])
    record = {key: trace.get(key) for key in ("success", "steps", "poses", "tasks_done")}
    record["events"] = [[e[0], e[1], e[-1]] for e in trace["events"]]
    record["steer_to"] = trace.get("steer_to")
    digest = hashlib.sha256(json.dumps(record).encode())
    return {
        "trial": _key(path, level, seed),
        "success": bool(trace["success"]),
        "steps": int(trace["steps"]),
        "hash": digest.hexdigest()[:16],
    }


def fingerprint(path: Path, level: str, seed: int) -> dict:
    """The outcome of one trial and a hash of its record."""
    mission = load_mission(path)
    spec = mission_trials(mission, [level], 1, seed)[0]
    trial = spec.simulate()
    digest = hashlib.sha256()
    for array in (trial.trajectory, trial.focal, trial.considered, trial.unpruned):
        digest.update(np.ascontiguousarray(array).tobytes())
    # step, kind and observers of every event (their other fields are free to change)
    events = [[int(e[0]), str(e[1]), [int(i) for i in e[-1]]] for e in trial.events]
    digest.update(json.dumps(events).encode())
    return {
        "trial": _key(path, level, seed),
        "success": bool(trial.success),
        "steps": int(trial.steps),
        "hash": digest.hexdigest()[:16],
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--sample", choices=("stress", "shipped", "nested", "collaborative"), default="stress"
    )
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--write", metavar="FILE", help="write the fingerprints (JSON lines)")
    group.add_argument("--compare", metavar="FILE", help="compare against stored fingerprints")
    parser.add_argument(
        "--before-switch",
        action="store_true",
        help="--compare: the file was written before the level switch (issue 37); its "
        "first/second/third are the rules' levels of today and plan-* the planner's",
    )
    args = parser.parse_args()
    cases = _cases(args.sample)
    by_trace = args.sample in ("nested", "collaborative")
    fingerprint_of = trace_fingerprint if by_trace else fingerprint
    if args.write:
        with open(args.write, "w", encoding="utf-8") as out:
            for case in cases:
                out.write(json.dumps(fingerprint_of(*case)) + "\n")
                out.flush()
        print(f"{len(cases)} trials written to {args.write}")
        return 0
    names = {}
    if args.before_switch:
        names = OLD_JOINT_NAMES if args.sample == "collaborative" else OLD_NAMES
    stored = {}
    with open(args.compare, encoding="utf-8") as handle:
        for line in handle:
            row = json.loads(line)
            row["trial"] = renamed(row["trial"], names)
            stored[row["trial"]] = row
    same = differ = 0
    for case in cases:
        before = stored.get(_key(*case))
        if before is None:  # not fingerprinted then: not simulated now
            continue
        now = fingerprint_of(*case)
        if before == now:
            same += 1
        else:
            differ += 1
            print(f"differs: {now['trial']}: {before} -> {now}")
    print(f"{same} identical, {differ} different, of {same + differ} compared")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
