"""The vectorised environment: the simulator's world, stepped as arrays."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("gymnasium")
pytest.importorskip("pettingzoo")

from epistemica.del_.errors import InvalidArgumentError
from epistemica.mission import load_mission
from epistemica.sim.engine.env import MissionEnv
from epistemica.sim.engine.env_registry import PaperFamily
from epistemica.sim.engine.vector_env import VectorMissionEnv

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("mission", ["rendezvous", "allocation"])
def test_without_noise_each_copy_is_the_single_envs_trial(mission):
    """With no noise, copy k given the same actions is MissionEnv's trial of seed k: poses,
    estimates, rewards and ends, step by step."""
    family = PaperFamily(mission, 3, 3, process_noise=0.0, position_noise=0.0,
                         sensing_range=9.0, max_steps=40)  # fmt: skip
    vec = VectorMissionEnv(family, num_envs=3)
    batch = vec.reset(seed=5)
    singles = [MissionEnv(family) for _ in range(3)]
    views = [env.reset(seed=5 + k)[0] for k, env in enumerate(singles)]
    rng = np.random.default_rng(1)
    for _ in range(40):
        for k, view in enumerate(views):
            for i, robot in enumerate(["r1", "r2", "r3"]):
                assert np.allclose(batch["teammates"][k, i], view[robot]["teammates"], atol=1e-4)
                assert batch["known_goals"][k, i].tolist() == view[robot]["known_goals"].tolist()
                assert np.array_equal(batch["seen"][k, i], view[robot]["seen"])
        actions = np.stack([rng.uniform([0, -1], [1.2, 1], size=(3, 2)) for _ in range(3)])
        batch, rewards, terminated, truncated = vec.step(actions)
        ended = terminated | truncated
        for k, env in enumerate(singles):
            out = env.step({r: actions[k, i] for i, r in enumerate(["r1", "r2", "r3"])})
            views[k], reward, term, trunc = out[0], out[1]["r1"], out[2]["r1"], out[3]["r1"]
            assert rewards[k] == pytest.approx(reward, abs=1e-9)
            assert (terminated[k], truncated[k]) == (term, trunc)
        if ended.any():
            break
    assert ended.any()
    # A copy that ended starts the family's next seed, in order.
    fresh = iter(range(8, 8 + int(ended.sum())))
    assert vec.seeds.tolist() == [next(fresh) if ended[k] else 5 + k for k in range(3)]


def test_the_next_seeds_follow_in_order_and_actions_are_checked():
    vec = VectorMissionEnv(PaperFamily("rendezvous", 2, 2, max_steps=3), num_envs=2)
    vec.reset(seed=0)
    for _ in range(3):
        *_, truncated = vec.step(np.zeros((2, 2, 2)))
    assert truncated.all() and vec.seeds.tolist() == [2, 3]
    with pytest.raises(InvalidArgumentError, match=r"finite \(2, 2, 2\) array"):
        vec.step(np.zeros((2, 3, 2)))
    with pytest.raises(InvalidArgumentError, match="whole number >= 1"):
        VectorMissionEnv(PaperFamily("rendezvous", 2, 2), num_envs=0)


def test_what_the_batch_does_not_model_is_refused():
    mission = load_mission(ROOT / "specs" / "events" / "door_closes.epi")
    with pytest.raises(InvalidArgumentError, match="observation events") as info:
        VectorMissionEnv(mission, num_envs=2)
    assert "MissionEnv" in info.value.hint
