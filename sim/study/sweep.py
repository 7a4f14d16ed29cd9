"""Monte Carlo sweeps: trials as (world, level, seed), run locally or on a Dask cluster.

A :class:`TrialSpec` names one trial: a :class:`World` (a cell of the published protocol,
:class:`ProtocolWorld`, or a mission file), a level and a seed; its id is a hash of the
three, so the same trial has the same id in every sweep and on every machine.
:func:`run_sweep` runs the trials a :class:`~epistemica.sim.study.store.ResultStore` does not
hold yet, on local processes (``concurrent.futures``) or, given a scheduler address, on a
Dask cluster (the optional extra ``epistemica[cluster]``), and stores each row as it
arrives. Workers only compute; the driving process alone writes the file.

Examples
--------
>>> specs = plan_sweep(["rendezvous"], [2], [2, 3], ["zero", "convention"], trials=2)
>>> len(specs), specs[0].seed, specs[-1].seed
(8, 0, 1)
>>> run_trial(specs[0])["id"] == specs[0].id
True
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.simulate import simulate
from epistemica.sim.engine.trial import Trial
from epistemica.sim.kinds.registry import kind_named
from epistemica.sim.policies.levels import make_policy
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.study._executors import run_cluster, run_local
from epistemica.sim.study.provenance import code_version
from epistemica.sim.study.store import ResultStore
from epistemica.sim.study.trace import encode, trial_trace

__all__ = [
    "MAX_TRIALS",
    "ProtocolWorld",
    "TrialSpec",
    "World",
    "check_trials",
    "plan_sweep",
    "run_sweep",
    "run_trial",
    "spec_columns",
]


class World(Protocol):
    """What a trial is drawn from: the published protocol's cells, a mission file."""

    mission: str  # the mission kind (the results table's column)
    robots: int
    goals: int
    options: tuple  # (name, value) pairs kept with the results

    def trial_id(self, reasoning: str, seed: int) -> str:
        """A stable 16-hex-digit id of a trial of this world."""

    def scenario(self, seed: int) -> Scenario:
        """The trial's scenario."""

    def policies(self, seed: int) -> dict[int, str]:
        """Robots that follow a level of their own (ad hoc teammates)."""

    @property
    def parameters(self) -> ActiveParameters:
        """The active-inference levels' parameters."""


def _digest(value) -> str:
    text = json.dumps(value, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class ProtocolWorld(NamedTuple):
    """A cell of the published protocol: geometry and sensors drawn from each seed
    (:meth:`Scenario.paper`), with further :class:`Scenario` fields as ``options``."""

    mission: str
    robots: int
    goals: int
    options: tuple = ()

    def trial_id(self, reasoning: str, seed: int) -> str:
        return _digest([self.mission, self.robots, self.goals, reasoning, seed, list(self.options)])

    def scenario(self, seed: int) -> Scenario:
        return Scenario.paper(self.mission, self.robots, self.goals, seed, **dict(self.options))

    def policies(self, seed: int) -> dict[int, str]:
        return {}

    @property
    def parameters(self) -> ActiveParameters:
        return ActiveParameters()


@dataclass(frozen=True)
class TrialSpec:
    """One trial: a world, a reasoning level and a seed (noise and random draws)."""

    world: World
    reasoning: str
    seed: int

    @property
    def id(self) -> str:
        """A stable 16-hex-digit id: the same trial has the same id on every machine."""
        return self.world.trial_id(self.reasoning, self.seed)

    @property
    def mission(self) -> str:
        return self.world.mission

    @property
    def robots(self) -> int:
        return self.world.robots

    @property
    def goals(self) -> int:
        return self.world.goals

    @property
    def options(self) -> tuple:
        return self.world.options

    def scenario(self) -> Scenario:
        """The trial's scenario."""
        return self.world.scenario(self.seed)

    def simulate(self, scenario: Scenario | None = None) -> Trial:
        """Run the trial (on ``scenario``, if it was built already)."""
        return simulate(
            self.scenario() if scenario is None else scenario,
            self.reasoning,
            seed=self.seed,
            policies=self.world.policies(self.seed),
            parameters=self.world.parameters,
        )


def plan_sweep(
    missions: Sequence[str],
    robots: Sequence[int],
    goals: Sequence[int] | None,
    reasoning: Sequence[str],
    trials: int,
    seed: int = 0,
    options: dict | None = None,
) -> list[TrialSpec]:
    """Every trial of a sweep, validated before anything runs.

    ``goals=None`` means: allocation as many goals as robots, multitask 20 tasks, and
    rendezvous as many goals as robots. Trial ``t`` of every cell uses seed ``seed + t``,
    so every level and every cell of one team size share geometry and noise per seed.
    """
    check_trials(trials, seed)
    for level in reasoning:
        make_policy(level)  # unknown names fail here, not in a worker
    opts = tuple(sorted((options or {}).items()))
    specs = []
    for mission in missions:
        for n in robots:
            cell_goals = goals or [_default_goals(mission, n)]
            for m in cell_goals:
                if kind_named(mission).distinct and m < n:
                    continue  # not a valid allocation cell
                Scenario.paper(mission, n, m, seed, **dict(opts))  # validates the cell
                for level in reasoning:
                    world = ProtocolWorld(mission, n, m, opts)
                    specs.extend(TrialSpec(world, level, seed + t) for t in range(trials))
    if not specs:
        raise InvalidArgumentError(
            "the sweep has no valid cell", hint="allocation needs at least as many goals as robots"
        )
    return specs


#: The most trials per cell (or per level of a mission) a sweep plans.
MAX_TRIALS = 1_000_000


def check_trials(trials, seed) -> None:
    """Refuse a trial count or first seed that a results file cannot hold."""
    if isinstance(trials, bool) or not isinstance(trials, int) or not 1 <= trials <= MAX_TRIALS:
        raise InvalidArgumentError(
            f"trials must be an integer in 1..{MAX_TRIALS:,}, got {trials!r}", hint="e.g. 50"
        )
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**62:
        raise InvalidArgumentError(
            f"seed must be an integer in 0..2**62, got {seed!r}", hint="e.g. 0"
        )


def _default_goals(mission: str, n: int) -> int:
    return kind_named(mission).default_goals(n)


def run_trial(spec: TrialSpec, traces: bool = True) -> dict:
    """Run one trial and return its result row (see :data:`epistemica.sim.study.store.COLUMNS`),
    with its per-step trace (:mod:`epistemica.sim.study.trace`, compressed) unless ``traces`` is
    False. A joint mission's trials keep no configuration sets (``unpruned`` is None)."""
    started = time.perf_counter()
    scenario = spec.scenario()
    trial = spec.simulate(scenario)
    elapsed = time.perf_counter() - started
    return spec_columns(spec) | {
        "success": int(trial.success),
        "steps": trial.steps,
        "completion_step": trial.completion_step,
        "wall_time": elapsed,
        "decision_ms": float(np.mean(trial.decision_time) * 1e3) if trial.steps else 0.0,
        "considered": float(np.mean(trial.considered)) if trial.steps else 0.0,
        "unpruned": _mean(trial.unpruned, trial.steps),
        "trace": encode(trial_trace(scenario, trial)) if traces else None,
    }


def _mean(values: np.ndarray | None, steps: int) -> float | None:
    if values is None:
        return None
    return float(np.mean(values)) if steps else 0.0


def spec_columns(spec: TrialSpec) -> dict:
    """The columns of a trial's results row that name it (and the code version)."""
    return {
        "id": spec.id,
        "mission": spec.mission,
        "robots": spec.robots,
        "goals": spec.goals,
        "reasoning": spec.reasoning,
        "seed": spec.seed,
        "options": json.dumps(dict(spec.options), sort_keys=True),
        "version": code_version(),
    }


def run_sweep(
    specs: Iterable[TrialSpec],
    store: ResultStore,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[dict], None] | None = None,
    traces: bool = True,
) -> tuple[int, int]:
    """Run the trials ``store`` does not hold yet; store each row as it arrives.

    Returns ``(ran, skipped)``: skipped trials were stored already or run by another sweep
    on the same file (each trial is claimed just before it is started). An interruption
    (Ctrl-C) stops the workers at once and leaves every finished trial stored; running
    again with the same store runs only what is missing.
    """
    if workers is not None and (isinstance(workers, bool) or workers < 1):
        raise InvalidArgumentError(f"workers must be >= 1, got {workers!r}", hint="e.g. 2")
    specs = list({s.id: s for s in specs}.values())  # a level named twice runs once
    claimed = (s for s in specs if store.claim(s.id))
    task = functools.partial(run_trial, traces=traces)
    if scheduler:
        rows = run_cluster(task, claimed, scheduler)
    else:
        rows = run_local(task, claimed, workers)
    ran = 0
    with contextlib.closing(rows):
        for row in rows:
            store.add(row)
            ran += 1
            if progress is not None:
                progress(row)
    return ran, len(specs) - ran
