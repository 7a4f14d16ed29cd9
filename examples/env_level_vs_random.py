"""One of our reasoning levels and a random policy, side by side, through the environment.

Both drive every robot of ``specs/rendezvous.epi`` through
:class:`epistemica.sim.engine.env.MissionEnv` on the same seeds (the same layouts and the same
noise); the level's actions come from ``env.level_actions``, the random ones from the action
spaces (seeded).

    python examples/env_level_vs_random.py --level convention --trials 5
"""

from __future__ import annotations

import argparse
from pathlib import Path

from epistemica.mission import load_mission
from epistemica.sim.engine.env import MissionEnv

MISSION = Path(__file__).resolve().parents[1] / "specs" / "rendezvous.epi"


def play(env: MissionEnv, seed: int, level: str | None) -> tuple[bool, int, float]:
    """One episode: (success, steps, team return) with ``level`` or random actions."""
    env.reset(seed=seed)
    for k, agent in enumerate(env.possible_agents):
        env.action_space(agent).seed(seed * 100 + k)
    total = 0.0
    while env.agents:
        if level is None:
            actions = {a: env.action_space(a).sample() for a in env.agents}
        else:
            actions = env.level_actions(level)
        _, rewards, _, _, _ = env.step(actions)
        total += next(iter(rewards.values()))
    trial = env.trial()
    return trial.success, trial.steps, total


def main(argv: list[str] | None = None) -> dict[str, list[tuple[bool, int, float]]]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", default="convention")
    parser.add_argument("--trials", type=int, default=5)
    args = parser.parse_args(argv)
    env = MissionEnv(load_mission(MISSION))
    results = {}
    for name, level in ((args.level, args.level), ("random", None)):
        results[name] = [play(env, seed, level) for seed in range(args.trials)]
        wins = sum(r[0] for r in results[name])
        steps = sum(r[1] for r in results[name]) / args.trials
        reward = sum(r[2] for r in results[name]) / args.trials
        print(f"{name:>12}: {wins}/{args.trials} successes, {steps:.1f} steps, return {reward:.3f}")
    return results


if __name__ == "__main__":
    main()
