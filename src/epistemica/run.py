"""Running a mission file's study: its trials, stored, summarised, drawn.

A mission's trial is (mission text, level, seed): a
:class:`~epistemica.sim.study.sweep.TrialSpec` over the file as a :class:`MissionWorld`, whose id
hashes the three, so a study interrupted at any moment resumes with the trials it misses, and
the same file gives the same trials on every machine. Trials run through the simulator's
sweep machinery (:func:`epistemica.sim.study.sweep.run_sweep`: local processes, results in
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
from epistemica.mission import Mission, load_mission, parse_mission
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.policies.levels import make_level
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.study.store import ResultStore
from epistemica.sim.study.sweep import TrialSpec, check_trials, run_sweep

__all__ = ["MissionWorld", "mission_trials", "run_study", "team_trials"]


@functools.lru_cache(maxsize=16)
def _compiled(source: str, filename: str, team: int | None) -> Mission:
    return parse_mission(source, filename, team)


@dataclass(frozen=True)
class MissionWorld:
    """A mission file as a :class:`~epistemica.sim.study.sweep.World`: its text (compiled once
    per process) and, for a file whose robots are ``r1..rN``, the team size N; a trial's id
    is its text, N, level and seed."""

    source: str
    filename: str
    team: int | None = None

    @property
    def compiled(self) -> Mission:
        return _compiled(self.source, self.filename, self.team)

    @property
    def mission(self) -> str:
        """The mission kind's name (the results table's ``mission`` column)."""
        return self.compiled.kind.name

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
        key = [self.source, reasoning, seed] + ([] if self.team is None else [self.team])
        text = json.dumps(key)
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
    levels = list(dict.fromkeys(levels))  # a level named twice runs once
    for level in levels:  # unknown names fail here, not in a worker
        make_level(mission.kind, level)
    first = mission.study.seed if seed is None else seed
    check_trials(trials, first)
    world = MissionWorld(mission.source, mission.filename, mission.team)
    return [TrialSpec(world, level, first + t) for level in levels for t in range(trials)]


def team_trials(
    path,
    teams: Sequence[int] | None,
    levels: Sequence[str] | None = None,
    trials: int | None = None,
    seed: int | None = None,
) -> list[TrialSpec]:
    """The trials of the study of the mission file at ``path`` at each team size of
    ``teams``: N of its spans ``r1..rN`` (``None``: the file's own ``simulate robots N``,
    or its robots as written)."""
    if teams is None:
        return mission_trials(load_mission(path), levels, trials, seed)
    specs = []
    for team in teams:
        mission = load_mission(path, team)
        if mission.team is None:
            raise InvalidArgumentError(
                f"{path} does not declare its team size as a parameter",
                hint="write its robots (and goals) as spans r1..rN, g1..gN and add "
                "'simulate robots 3' (the default N)",
            )
        specs.extend(mission_trials(mission, levels, trials, seed))
    return specs


def run_study(
    trials: Sequence[TrialSpec],
    store: ResultStore,
    *,
    workers: int | None = None,
    progress: Callable[[dict], None] | None = None,
) -> tuple[int, int]:
    """Run the trials ``store`` does not hold yet; ``(ran, skipped)``."""
    return run_sweep(trials, store, workers=workers, progress=progress)
