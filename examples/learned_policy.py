"""Does a learned, communication-free policy find what third-order reasoning finds?

Trains one policy shared by every robot of a mission (parameter sharing: each robot is one
sample of the same network, acting on its own observation only, so the team never
communicates) with Stable-Baselines3's PPO on the mission's layouts, then runs it on the
mission study's own seeds beside the reasoning levels, and prints both.

The learner sees, each step, what :class:`epistemica.sim.engine.env.MissionEnv` gives a robot
with ``epistemic=True``: its pose, where it places its teammates, which goals it knows of,
the goals it takes each teammate to know of, the step. ``--egocentric`` (default) rewrites
every position as an offset in the robot's own frame, in workspaces (the same information:
the robot's own pose is exact); ``--raw`` flattens the observation as it is (metres, the
step one-hot). Actions are normalised (``[-1, 1]²``). ``--normalize`` (default) wraps the
vector env in Stable-Baselines3's ``VecNormalize`` (running mean and variance of the
observations and of the discounted return). ``--log-std -1`` (default) starts PPO with
less exploration noise than Stable-Baselines3's 0, which never let three robots stand
together on a goal. Training uses seeds from 10,000 on, evaluation the study's seeds
(``simulate trials N seed S`` of the mission file) or ``--eval-seed S``, so a layout seen in
training is never scored; the defaults were chosen on seeds 90,000-90,019
(docs/learning.md). It prints the learning curve (mean team return and successes over the
training trials), then each level's and the learned policy's successes, mean steps and,
for a gathering mission, the goal the team met at.

Needs the ``learn`` extra: ``pip install "epistemica[learn]"`` (Stable-Baselines3, which
needs PyTorch: install a CPU build of torch first, ``pip install torch --index-url
https://download.pytorch.org/whl/cpu``, or pip fetches a large CUDA build).

    python examples/learned_policy.py specs/rendezvous.epi --timesteps 1000000 --save runs/m
    python examples/learned_policy.py specs/rendezvous.epi --load runs/m --eval-seed 20000
    python examples/learned_policy.py specs/rendezvous.epi --timesteps 2000 --eval 5
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import torch
from gymnasium import spaces
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecEnv, VecNormalize

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.env import MissionEnv

TRAIN_SEEDS = 10_000  # training layouts start here, far from any study's seeds
CURVE_POINTS = 10  # rows of the printed learning curve


class Features:
    """One robot's observation (a ``MissionEnv`` dict) as a float32 vector.

    ``egocentric``: the robot's position (centred, in workspaces), the cosine and sine of
    its heading, every teammate's and every known goal's offset in the robot's own frame
    (in workspaces) and distance, the binary parts as they are, the step over the step
    limit. Otherwise the dict flattened as Gymnasium flattens it (metres, step one-hot).
    """

    def __init__(self, env: MissionEnv, egocentric: bool) -> None:
        self.space = env.observation_space(env.possible_agents[0])
        self.egocentric = egocentric
        s = env.scenario
        self.width, self.limit = float(s.workspace), float(max(s.max_steps, 1))
        size = spaces.flatdim(self.space)
        if egocentric:
            binary = [k for k in self.space if isinstance(self.space[k], spaces.MultiBinary)]
            size = 5 + 3 * (s.n_robots + s.n_goals)
            size += sum(int(np.prod(self.space[k].shape)) for k in binary)
        self.box = spaces.Box(-np.inf, np.inf, shape=(size,), dtype=np.float32)

    def __call__(self, view: dict) -> np.ndarray:
        if not self.egocentric:
            return spaces.flatten(self.space, view).astype(np.float32)
        x, y, heading = (float(v) for v in view["pose"])
        turn = np.array([[np.cos(heading), -np.sin(heading)], [np.sin(heading), np.cos(heading)]])
        known = np.asarray(view["known_goals"], dtype=float)
        mates = self._relative(view["teammates"], (x, y), turn)
        goals = self._relative(view["goals"], (x, y), turn) * known[:, None]
        own = [x / self.width - 0.5, y / self.width - 0.5, np.cos(heading), np.sin(heading)]
        binary = [
            np.ravel(v) for k, v in view.items() if isinstance(self.space[k], spaces.MultiBinary)
        ]
        parts = [own, mates.ravel(), goals.ravel(), *binary, [view["step"] / self.limit]]
        return np.concatenate(parts).astype(np.float32)

    def _relative(self, points, origin, turn: np.ndarray) -> np.ndarray:
        """Offsets of ``points`` from ``origin`` in the robot's frame, and their lengths
        (in workspaces), one row ``(forward, left, distance)`` each."""
        offsets = (np.asarray(points, dtype=float) - np.array(origin)) @ turn / self.width
        return np.column_stack([offsets, np.hypot(offsets[:, 0], offsets[:, 1])])


class SharedPolicyEnv(VecEnv):
    """``copies`` trials of a mission as one Stable-Baselines3 vector env whose entries
    are the robots (``copies × n``): one policy drives every robot, each on its own
    observation. A trial that ends restarts on the next training seed. Every finished
    trial's team return (the environment's reward) and success is kept in ``episodes``.

    ``gather``: the weight of a second potential-based shaping term (Ng, Harada and
    Russell 1999: it leaves the optimal policies as they are), minus the mean distance
    between two robots in workspaces, read from ``MissionEnv.state()``: the team is
    rewarded for closing up, which a rendezvous asks for whatever the goal.
    """

    def __init__(
        self, mission, copies: int, egocentric: bool, shaping: float, gather: float = 0.0
    ) -> None:
        self.envs = [
            MissionEnv(mission, epistemic=True, normalized=True, shaping=shaping)
            for _ in range(copies)
        ]
        self.agents = list(self.envs[0].possible_agents)
        self.features = Features(self.envs[0], egocentric)
        action = self.envs[0].action_space(self.agents[0])
        self.render_mode = None
        super().__init__(copies * len(self.agents), self.features.box, action)
        self.next_seed = TRAIN_SEEDS
        self.episodes: list[tuple[float, bool]] = []
        self.gather = gather
        self.spread = np.zeros(copies)

    def _flat(self, views: dict) -> np.ndarray:
        return np.stack([self.features(views[a]) for a in self.agents])

    def _restart(self, k: int) -> np.ndarray:
        env = self.envs[k]
        views, _ = env.reset(seed=self.next_seed)
        self.next_seed += 1
        self.spread[k] = self._spread(env)
        return self._flat(views)

    def _spread(self, env: MissionEnv) -> float:
        """Minus the mean distance between two robots (in workspaces): 0 when together."""
        n = env.scenario.n_robots
        if not self.gather or n < 2:
            return 0.0
        xy = env.state()[: 3 * n].reshape(n, 3)[:, :2]
        gaps = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))
        return -float(gaps.sum()) / (n * (n - 1) * self.features.width)

    def reset(self) -> np.ndarray:
        self.next_seed = TRAIN_SEEDS
        return np.concatenate([self._restart(k) for k in range(len(self.envs))])

    def step_async(self, actions: np.ndarray) -> None:
        self.actions = np.asarray(actions).reshape(len(self.envs), len(self.agents), -1)

    def step_wait(self):
        obs, rewards, dones, infos = [], [], [], []
        for k, (env, chosen) in enumerate(zip(self.envs, self.actions, strict=True)):
            actions = dict(zip(self.agents, chosen, strict=True))
            views, reward, terminated, truncated, _ = env.step(actions)
            flat = self._flat(views)
            over = not env.agents
            spread = self._spread(env)
            bonus, self.spread[k] = self.gather * (spread - self.spread[k]), spread
            for j, agent in enumerate(self.agents):
                info = {}
                if over:
                    info = {
                        "terminal_observation": flat[j],
                        "TimeLimit.truncated": truncated[agent],
                    }
                infos.append(info)
                rewards.append(reward[agent] + bonus)
                dones.append(over)
            if over:
                first = self.agents[0]
                self.episodes.append((env.returns[first], bool(terminated[first])))
            obs.append(self._restart(k) if over else flat)
        return (np.concatenate(obs), np.array(rewards, dtype=np.float32), np.array(dones),
                infos)  # fmt: skip

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


def learned_trial(model, mission, seed: int, features: Features, normalizer=None):
    """The trial of ``seed`` with every robot driven by the learned policy (observations
    normalised with the training statistics, frozen, when ``normalizer`` is given)."""
    env = MissionEnv(mission, epistemic=True, normalized=True)
    views, _ = env.reset(seed=seed)
    while env.agents:
        obs = np.stack([features(views[a]) for a in env.agents])
        if normalizer is not None:
            obs = normalizer.normalize_obs(obs)
        actions, _ = model.predict(obs, deterministic=True)
        views, *_ = env.step(dict(zip(env.agents, actions, strict=True)))
    return env.trial()


def learning_curve(episodes: list[tuple[float, bool]], points: int = CURVE_POINTS) -> list:
    """``(trials so far, mean team return, share of successes)`` over ``points`` equal
    slices of the training trials, in order (fewer when there are fewer trials)."""
    if not episodes:
        return []
    rows = []
    for part in np.array_split(np.arange(len(episodes)), min(points, len(episodes))):
        returns = [episodes[k][0] for k in part]
        won = [episodes[k][1] for k in part]
        rows.append((int(part[-1]) + 1, float(np.mean(returns)), float(np.mean(won))))
    return rows


def arguments() -> argparse.Namespace:
    """The command line (every default chosen on training seeds only)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", help="a mission file (rendezvous, allocation, ...)")
    parser.add_argument("--timesteps", type=int, default=1_000_000, help="robot-steps of PPO")
    parser.add_argument("--copies", type=int, default=8, help="trials stepped together")
    parser.add_argument("--eval", type=int, default=None, help="study seeds (default: all)")
    parser.add_argument(
        "--eval-seed",
        type=int,
        default=None,
        help="first evaluation seed (default: the study's; defaults were "
        "chosen with seeds from 90,000, unseen in training)",
    )
    parser.add_argument("--seed", type=int, default=0, help="PPO's seed")
    view = parser.add_mutually_exclusive_group()
    view.add_argument(
        "--egocentric",
        dest="egocentric",
        action="store_true",
        default=True,
        help="offsets in the robot's frame, in workspaces (default)",
    )
    view.add_argument(
        "--raw",
        dest="egocentric",
        action="store_false",
        help="the observation flattened as it is (metres)",
    )
    parser.add_argument(
        "--normalize",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="VecNormalize observations and reward (default on)",
    )
    parser.add_argument("--shaping", type=float, default=1.0, help="MissionEnv's shaping")
    parser.add_argument(
        "--gather",
        type=float,
        default=0.0,
        help="weight of the team-spread shaping (SharedPolicyEnv)",
    )
    parser.add_argument("--gamma", type=float, default=0.99, help="PPO's discount")
    parser.add_argument("--n-steps", type=int, default=128, help="rollout per robot")
    parser.add_argument("--ent-coef", type=float, default=0.0, help="PPO's entropy bonus")
    parser.add_argument("--net", type=int, nargs="+", default=[64, 64], help="hidden sizes")
    parser.add_argument(
        "--log-std",
        type=float,
        default=-1.0,
        help="initial log std of the actions (0: std 1 over [-1, 1])",
    )
    parser.add_argument(
        "--save", default=None, help="save the model (PATH.zip) and VecNormalize (PATH.pkl)"
    )
    parser.add_argument("--load", default=None, help="evaluate a saved model, no training")
    return parser.parse_args()


def train(args: argparse.Namespace, mission) -> tuple:
    """PPO on the training seeds: the model, the vector env, its VecNormalize (or None)."""
    env = SharedPolicyEnv(mission, args.copies, args.egocentric, args.shaping, args.gather)
    venv = VecNormalize(env, gamma=args.gamma) if args.normalize else env
    steps = max(8, min(args.n_steps, args.timesteps // env.num_envs))  # per robot per rollout
    batch = max(8, steps * env.num_envs // 4)  # four minibatches per epoch
    policy = {"net_arch": list(args.net), "log_std_init": args.log_std}
    model = PPO("MlpPolicy", venv, n_steps=steps, batch_size=batch, n_epochs=4,
                gamma=args.gamma, ent_coef=args.ent_coef, policy_kwargs=policy,
                seed=args.seed, verbose=0, device="cpu")  # fmt: skip
    model.learn(total_timesteps=args.timesteps)
    if args.normalize:
        venv.training = False
    return model, env, venv if args.normalize else None


def restore(args: argparse.Namespace, mission) -> tuple:
    """A model ``--save`` wrote (``--load PATH``), as :func:`train` returns it."""
    env = SharedPolicyEnv(mission, args.copies, args.egocentric, args.shaping, args.gather)
    model = PPO.load(f"{args.load}.zip", device="cpu")
    normalizer = None
    if args.normalize:
        normalizer = VecNormalize.load(f"{args.load}.pkl", env)
        normalizer.training = False
    return model, env, normalizer


def meeting_goal(scenario, trial) -> int | None:
    """The goal a successful gathering trial ended at (the goal nearest the team's final
    centroid), or None for a failure."""
    if not trial.success:
        return None
    centre = trial.trajectory[-1, :, :2].mean(axis=0)
    return int(np.argmin(np.hypot(*(scenario.goals - centre).T)))


def report(mission, rows: list, seeds) -> None:
    """Successes, mean steps of the successes and, per row, where the team met (for a
    gathering mission) and on how many seeds at the same goal as the last level."""
    kinds = mission.scenario(seeds[0]).kind
    met = {
        name: [meeting_goal(mission.scenario(s), t) for s, t in zip(seeds, trials, strict=True)]
        for name, trials in rows
    }
    reference = rows[-2][0] if len(rows) > 1 else None
    print(f"{'level':<16} {'successes':>10} {'mean steps (successes)':>24}  met at")
    for name, trials in rows:
        won = [t.steps for t in trials if t.success]
        mean = f"{np.mean(won):.1f}" if won else "-"
        line = f"{name:<16} {len(won):>5}/{len(trials):<4} {mean:>24}"
        if kinds.gathers:
            names = mission.scenario(seeds[0]).goal_names
            counts = np.bincount([g for g in met[name] if g is not None], minlength=len(names))
            where = " ".join(f"{g}:{c}" for g, c in zip(names, counts, strict=True) if c)
            same = sum(
                a is not None and a == b for a, b in zip(met[name], met[reference], strict=True)
            )
            line += f"  {where or '-'} (as {reference}: {same})"
        print(line)


def main() -> None:
    args = arguments()
    torch.set_num_threads(1)  # small networks: threads only contend
    mission = load_mission(args.mission)
    wall, cpu = time.perf_counter(), time.process_time()
    if args.load:
        model, env, normalizer = restore(args, mission)
    else:
        model, env, normalizer = train(args, mission)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    if args.save:
        model.save(f"{args.save}.zip")
        if normalizer is not None:
            normalizer.save(f"{args.save}.pkl")
    study = mission.study
    first = study.seed if args.eval_seed is None else args.eval_seed
    seeds = range(first, first + (args.eval or study.trials))
    done = f"loaded from {args.load}" if args.load else f"{args.timesteps} robot-steps"
    print(f"{mission.name}: PPO, one policy shared by {len(env.agents)} robots, "
          f"{done} in {wall:.0f} s wall, {cpu:.0f} s CPU; "
          f"{len(seeds)} seeds from {first}")  # fmt: skip
    print(f"{'curve: trials':<16} {'mean return':>12} {'successes':>10}")
    for trials, mean, share in learning_curve(env.episodes):
        print(f"{'curve':<8} {trials:>7} {mean:>12.3f} {share:>10.2f}")
    rows = []
    for level in study.levels:
        trials = [
            simulate(mission.scenario(s), level, seed=s, policies=mission.policies(s),
                     parameters=mission.parameters)
            for s in seeds
        ]  # fmt: skip
        rows.append((level, trials))
    learned = [learned_trial(model, mission, s, env.features, normalizer) for s in seeds]
    rows.append(("learned (PPO)", learned))
    report(mission, rows, seeds)


if __name__ == "__main__":
    main()
