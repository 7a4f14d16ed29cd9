"""Random streams of one trial, all derived from its seed.

Each consumer has a stream of its own (geometry, sensor types, per robot its observation
noise, its process noise and its policy, and the mission file's draws: who knows which
goal, which teammate is ad hoc), so what one consumer draws never
shifts another's draws: every reasoning level sees the same geometry and the same noise.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["Streams", "trial_streams"]


class Streams(NamedTuple):
    """Independent generators of one trial."""

    geometry: np.random.Generator
    sensors: np.random.Generator
    observation: tuple[np.random.Generator, ...]
    process: tuple[np.random.Generator, ...]
    policy: tuple[np.random.Generator, ...]
    mission: np.random.Generator


def trial_streams(seed: int, n_robots: int) -> Streams:
    """The generators of trial ``seed`` for ``n_robots`` robots.

    Robot ``i``'s streams do not depend on the team size beyond ``i``: they are children
    ``i`` of fixed per-purpose sequences.

    Examples
    --------
    >>> a, b = trial_streams(3, 2), trial_streams(3, 5)
    >>> float(a.observation[1].random()) == float(b.observation[1].random())
    True
    """
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise InvalidArgumentError(
            f"seed must be an integer >= 0, got {seed!r}", hint="e.g. seed=0"
        )
    root = np.random.SeedSequence(int(seed))
    # Children are keyed by index: a sixth stream leaves the first five unchanged.
    geometry, sensors, observation, process, policy, mission = root.spawn(6)

    def per_robot(sequence: np.random.SeedSequence) -> tuple[np.random.Generator, ...]:
        return tuple(
            np.random.default_rng(
                np.random.SeedSequence(sequence.entropy, spawn_key=(*sequence.spawn_key, i))
            )
            for i in range(n_robots)
        )

    return Streams(
        np.random.default_rng(geometry),
        np.random.default_rng(sensors),
        per_robot(observation),
        per_robot(process),
        per_robot(policy),
        np.random.default_rng(mission),
    )
