"""Does a learned, communication-free policy find what third-order reasoning finds?

Trains one policy shared by every robot of a mission (parameter sharing: each robot is one
sample of the same network, acting on its own observation only, so the team never
communicates) with Stable-Baselines3's PPO on the mission's layouts, then runs it on the
mission study's own seeds beside the reasoning levels, and prints both.

The learner sees, each step, what :class:`epistemica.sim.engine.env.MissionEnv` gives a robot with
``epistemic=True``: its pose, where it places its teammates, which goals it knows of, the
goals it takes each teammate to know of, the step; flattened into one vector. Actions are
normalised (``[-1, 1]²``). Training uses seeds from 10,000 on, evaluation the study's seeds
(``simulate trials N seed S`` of the mission file), so a layout seen in training is never
scored.

Needs the ``learn`` extra: ``pip install "epistemica[learn]"`` (Stable-Baselines3, which
needs PyTorch: install a CPU build of torch first, ``pip install torch --index-url
https://download.pytorch.org/whl/cpu``, or pip fetches a large CUDA build).

    python examples/learned_policy.py specs/nested/private_goal_3.epi --timesteps 300000
    python examples/learned_policy.py specs/rendezvous.epi --timesteps 2000 --eval 5
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import torch
from gymnasium import spaces
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecEnv

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.env import MissionEnv

TRAIN_SEEDS = 10_000  # training layouts start here, far from any study's seeds


class SharedPolicyEnv(VecEnv):
    """``copies`` trials of a mission as one Stable-Baselines3 vector env whose entries
    are the robots (``copies × n``): one policy drives every robot, each on its own
    observation. A trial that ends restarts on the next training seed."""

    def __init__(self, mission, copies: int) -> None:
        self.envs = [MissionEnv(mission, epistemic=True, normalized=True) for _ in range(copies)]
        self.agents = list(self.envs[0].possible_agents)
        self.dict_space = self.envs[0].observation_space(self.agents[0])
        box = spaces.flatten_space(self.dict_space)
        action = self.envs[0].action_space(self.agents[0])
        self.render_mode = None
        super().__init__(copies * len(self.agents), box, action)
        self.next_seed = TRAIN_SEEDS
        self.views: list[dict] = []

    def _flat(self, views: dict) -> np.ndarray:
        return np.stack([spaces.flatten(self.dict_space, views[a]) for a in self.agents])

    def _restart(self, env: MissionEnv) -> np.ndarray:
        views, _ = env.reset(seed=self.next_seed)
        self.next_seed += 1
        return self._flat(views)

    def reset(self) -> np.ndarray:
        self.next_seed = TRAIN_SEEDS
        return np.concatenate([self._restart(env) for env in self.envs]).astype(np.float32)

    def step_async(self, actions: np.ndarray) -> None:
        self.actions = np.asarray(actions).reshape(len(self.envs), len(self.agents), -1)

    def step_wait(self):
        obs, rewards, dones, infos = [], [], [], []
        for env, chosen in zip(self.envs, self.actions, strict=True):
            actions = dict(zip(self.agents, chosen, strict=True))
            views, reward, _, truncated, _ = env.step(actions)
            flat = self._flat(views)
            over = not env.agents
            for k, agent in enumerate(self.agents):
                info = {}
                if over:
                    info = {
                        "terminal_observation": flat[k],
                        "TimeLimit.truncated": truncated[agent],
                    }
                infos.append(info)
                rewards.append(reward[agent])
                dones.append(over)
            obs.append(self._restart(env) if over else flat)
        return (np.concatenate(obs).astype(np.float32), np.array(rewards, dtype=np.float32),
                np.array(dones), infos)  # fmt: skip

    def close(self) -> None:
        for env in self.envs:
            env.close()

    def get_attr(self, attr_name, indices=None):
        return [getattr(self, attr_name)] * len(self._indices(indices))

    def set_attr(self, attr_name, value, indices=None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name, *args, indices=None, **kwargs):
        return [None] * len(self._indices(indices))

    def env_is_wrapped(self, wrapper_class, indices=None):
        return [False] * len(self._indices(indices))

    def _indices(self, indices):
        if indices is None:
            return range(self.num_envs)
        return [indices] if isinstance(indices, int) else indices


def learned_trial(model, mission, seed: int):
    """The trial of ``seed`` with every robot driven by the learned policy."""
    env = MissionEnv(mission, epistemic=True, normalized=True)
    space = env.observation_space(env.possible_agents[0])
    views, _ = env.reset(seed=seed)
    while env.agents:
        obs = np.stack([spaces.flatten(space, views[a]) for a in env.agents])
        actions, _ = model.predict(obs.astype(np.float32), deterministic=True)
        views, *_ = env.step(dict(zip(env.agents, actions, strict=True)))
    return env.trial()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", help="a mission file (rendezvous, allocation, ...)")
    parser.add_argument("--timesteps", type=int, default=300_000, help="robot-steps of PPO")
    parser.add_argument("--copies", type=int, default=8, help="trials stepped together")
    parser.add_argument("--eval", type=int, default=None, help="study seeds (default: all)")
    parser.add_argument("--seed", type=int, default=0, help="PPO's seed")
    args = parser.parse_args()
    torch.set_num_threads(1)  # small networks: threads only contend
    mission = load_mission(args.mission)
    env = SharedPolicyEnv(mission, args.copies)
    steps = max(8, min(128, args.timesteps // env.num_envs))  # per robot per rollout
    batch = max(8, steps * env.num_envs // 4)  # four minibatches per epoch
    model = PPO("MlpPolicy", env, n_steps=steps, batch_size=batch, n_epochs=4,
                seed=args.seed, verbose=0, device="cpu")  # fmt: skip
    started = time.perf_counter()
    model.learn(total_timesteps=args.timesteps)
    trained = time.perf_counter() - started
    study = mission.study
    seeds = range(study.seed, study.seed + (args.eval or study.trials))
    print(f"{mission.name}: PPO, one policy shared by {len(env.agents)} robots, "
          f"{args.timesteps} robot-steps in {trained:.0f} s; {len(seeds)} study seeds "
          f"from {study.seed}")  # fmt: skip
    rows = []
    for level in study.levels:
        trials = [
            simulate(mission.scenario(s), level, seed=s, policies=mission.policies(s),
                     parameters=mission.parameters)
            for s in seeds
        ]  # fmt: skip
        rows.append((level, trials))
    rows.append(("learned (PPO)", [learned_trial(model, mission, s) for s in seeds]))
    print(f"{'level':<16} {'successes':>10} {'mean steps (successes)':>24}")
    for name, trials in rows:
        won = [t.steps for t in trials if t.success]
        mean = f"{np.mean(won):.1f}" if won else "-"
        print(f"{name:<16} {len(won):>5}/{len(trials):<4} {mean:>24}")


if __name__ == "__main__":
    main()
