"""How the trials of a nested mission end when a robot heads for a goal its teammates cannot
conceive of (docs/results.md §7, "Why two missions miss").

For each trial of the mission at the level: whether some robot acts at step 0 or 1 on a
configuration that sends it to ``--goal`` (the goal only some robots know of: g4 in
``private_goal``, g5 in ``relocated``); if so, whether one of them stood on that goal for
``--wait`` steps or more (it waited there for the team), and whether the mission was done.

    python benchmarks/nested_outcomes.py specs/nested/private_goal_3.epi --goal g4 \
        --levels rules-third-shared,rules-third --seeds 0-99
"""

from __future__ import annotations

import argparse
from collections import Counter

import numpy as np

from epistemica.mission import load_mission
from epistemica.run import mission_trials
from epistemica.sim import simulate

OUTCOMES = (
    "nobody heads there",
    "heads there, leaves before waiting",
    "waits there, then success",
    "waits there, failure",
)


def outcome(path: str, level: str, seed: int, goal: str, wait: int) -> str:
    """The outcome (one of :data:`OUTCOMES`, with "failure" or "success" for the first
    two) of one trial."""
    spec = mission_trials(load_mission(path), [level], 1, seed)[0]
    scenario = spec.scenario()
    trial = simulate(scenario, level, seed=seed, policies=spec.world.policies(spec.seed))
    g = scenario.goal_names.index(goal)
    robots = np.arange(scenario.n_robots)
    # The first two decisions: an event at step 0 is seen after the robots' first one.
    heading = robots[(trial.focal[:2, robots, robots] == g).any(axis=0)]
    done = "success" if trial.success else "failure"
    if not heading.size:
        return f"{OUTCOMES[0]}, {done}"
    places = trial.trajectory[1:, heading, :2]
    on_goal = np.hypot(*(places - scenario.goals[g]).transpose(2, 0, 1)) <= scenario.success_radius
    if (on_goal.sum(axis=0) < wait).all():
        return f"{OUTCOMES[1]}, {done}"
    return OUTCOMES[2] if trial.success else OUTCOMES[3]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="+")
    parser.add_argument("--goal", required=True, help="the goal some robots cannot conceive of")
    parser.add_argument("--levels", default="rules-third-shared,rules-third")
    parser.add_argument("--seeds", default="0-99", help="first-last (inclusive)")
    parser.add_argument("--wait", type=int, default=5, help="steps on the goal that count")
    args = parser.parse_args()
    first, last = (int(x) for x in args.seeds.split("-"))
    for path in args.missions:
        for level in args.levels.split(","):
            counts = Counter(
                outcome(path, level, seed, args.goal, args.wait) for seed in range(first, last + 1)
            )
            print(f"{path} {level} (seeds {args.seeds}):")
            for name, count in sorted(counts.items()):
                print(f"  {count:4d}  {name}")


if __name__ == "__main__":
    main()
