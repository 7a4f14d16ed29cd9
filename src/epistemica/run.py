"""Running a mission file's study: its trials, stored, summarised, drawn.

A mission's trial is (mission text, level, seed): a
:class:`~epistemica.sim.sweep.TrialSpec` over the file as a :class:`MissionWorld`, whose id
hashes the three, so a study interrupted at any moment resumes with the trials it misses, and
the same file gives the same trials on every machine. Trials run through the simulator's
sweep machinery (:func:`epistemica.sim.sweep.run_sweep`: local processes, results in
SQLite written by the driving process only).

Examples
--------
>>> from epistemica.mission import parse_mission
>>> m = parse_mission("mission rendezvous\\nrobot a: range at random\\n"
...                   "robot b: bearing at random\\ngoal x at random\\ngoal y at random\\n")
>>> trials = mission_trials(m, levels=["convention"], trials=2)
>>> [t.seed for t in trials], trials[0].robots, trials[0].mission
([0, 1], 2, 'rendezvous')
"""

from __future__ import annotations

import functools
import hashlib
import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from epistemica.del_.errors import InvalidArgumentError
from epistemica.mission import Mission, parse_mission
from epistemica.sim.levels import make_policy
from epistemica.sim.parameters import ActiveParameters
from epistemica.sim.scenario import Scenario
from epistemica.sim.store import ResultStore
from epistemica.sim.sweep import TrialSpec, run_sweep

__all__ = ["MissionWorld", "mission_trials", "run_study"]


@functools.lru_cache(maxsize=8)
def _compiled(source: str, filename: str) -> Mission:
    return parse_mission(source, filename)


@dataclass(frozen=True)
class MissionWorld:
    """A mission file as a :class:`~epistemica.sim.sweep.World`: its text (compiled once
    per process), so a trial's id is its text, level and seed."""

    source: str
    filename: str

    @property
    def compiled(self) -> Mission:
        return _compiled(self.source, self.filename)

    @property
    def mission(self) -> str:
        """The mission kind (the results table's ``mission`` column)."""
        return self.compiled.kind

    @property
    def robots(self) -> int:
        return len(self.compiled.robots)

    @property
    def goals(self) -> int:
        return len(self.compiled.goals)

    @property
    def options(self) -> tuple:
        """The file's name, so that reports keep studies of different files apart."""
        return (("spec", self.compiled.name),)

    @property
    def parameters(self) -> ActiveParameters:
        return self.compiled.parameters

    def trial_id(self, reasoning: str, seed: int) -> str:
        text = json.dumps([self.source, reasoning, seed])
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def scenario(self, seed: int) -> Scenario:
        return self.compiled.scenario(seed)

    def policies(self, seed: int) -> dict[int, str]:
        return self.compiled.policies(seed)


def mission_trials(
    mission: Mission,
    levels: Sequence[str] | None = None,
    trials: int | None = None,
    seed: int | None = None,
) -> list[TrialSpec]:
    """The trials of ``mission``'s study (its ``simulate`` line, or the arguments)."""
    levels = list(mission.study.levels if levels is None else levels)
    trials = mission.study.trials if trials is None else trials
    if isinstance(trials, bool) or not isinstance(trials, int) or trials < 1:
        raise InvalidArgumentError(f"trials must be an integer >= 1, got {trials!r}", hint="20")
    for level in levels:
        make_policy(level)  # unknown names fail here, not in a worker
    first = mission.study.seed if seed is None else seed
    if isinstance(first, bool) or not isinstance(first, int) or first < 0:
        raise InvalidArgumentError(f"seed must be an integer >= 0, got {first!r}", hint="0")
    world = MissionWorld(mission.source, mission.filename)
    return [TrialSpec(world, level, first + t) for level in levels for t in range(trials)]


def run_study(
    trials: Sequence[TrialSpec],
    store: ResultStore,
    *,
    workers: int | None = None,
    progress: Callable[[dict], None] | None = None,
) -> tuple[int, int]:
    """Run the trials ``store`` does not hold yet; ``(ran, skipped)``."""
    return run_sweep(trials, store, workers=workers, progress=progress)
