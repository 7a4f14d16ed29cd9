"""A collaborative trial as a results row and a trace document, so that its study is
stored, resumed and summarised like every other mission's (:mod:`epistemica.sim.study.sweep`).

The trace is an ``epistemica-trace`` v2 document with the fields every trial has (names,
places, poses, events) and ``kind: "collaborative"`` with what is particular to it:

================  ==========================================================================
``needs``         ``m`` robots each task needs at once
``tasks_done``    ``m`` steps each task was done (-1: never)
``steer_to``      ``(T, n)`` the task each robot steered to (-1 exploring, -2 fetching)
``knows``         ``(T, n, m)`` 1 where robot ``i`` knew of task ``t``
``aware_since``   ``(n, n, m)`` the first step robot ``i`` knew that robot ``j`` knows of task
                  ``t`` (-1 never): the nested knowledge at every step
``events``        ``[step, name, [arguments], [observers]]``, arguments by name
================  ==========================================================================

It has no belief or configuration-set fields (a collaborative level keeps none).

Examples
--------
>>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
>>> s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1)
>>> columns = collaborative_columns(s, "first", 1)
>>> columns["steps"] == len(decode(columns["trace"])["poses"]) - 1
True
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from epistemica.sim.kinds.collaborative import (
    CollaborativeScenario,
    CollaborativeTrial,
    simulate_collaborative,
)
from epistemica.sim.kinds.tasks import COLLABORATIVE
from epistemica.sim.policies.collaborative_levels import CollaborativeParameters
from epistemica.sim.study.trace import FORMAT, VERSION, decode, encode

__all__ = ["collaborative_columns", "collaborative_trace", "decode"]


def collaborative_trace(s: CollaborativeScenario, trial: CollaborativeTrial) -> dict[str, Any]:
    """The trace document of ``trial`` (a trial of ``s``)."""
    events = [
        [int(step), str(name), [str(a) for a in args], [int(o) for o in observers]]
        for step, name, args, observers in trial.events
    ]
    return {
        "format": FORMAT,
        "version": VERSION,
        "kind": COLLABORATIVE.trace_kind,
        "robots": list(s.robot_names),
        "goals": list(s.task_names),
        "goal_positions": np.round(s.tasks, 2).tolist(),
        "needs": [int(k) for k in s.needs],
        "workspace": float(s.workspace),
        "sensing_range": float(s.sensing_range),
        "success_radius": float(s.completion_radius),
        "sensors": list(s.sensors),
        "policies": [trial.policy] * s.n_robots,
        "seed": int(trial.seed),
        "success": bool(trial.success),
        "steps": int(trial.steps),
        "poses": np.round(trial.trajectory, 2).tolist(),
        "tasks_done": [int(d) for d in trial.tasks_done],
        "steer_to": np.asarray(trial.targets, dtype=int).tolist(),
        "knows": np.asarray(trial.knows, dtype=int).tolist(),
        "aware_since": np.asarray(trial.aware_since, dtype=int).tolist(),
        "events": events,
    }


def collaborative_columns(
    s: CollaborativeScenario,
    level: str,
    seed: int,
    parameters: CollaborativeParameters | None = None,
    traces: bool = True,
) -> dict[str, Any]:
    """The outcome columns of a results row (:data:`epistemica.sim.study.store.COLUMNS`) for one
    collaborative trial; it keeps no configuration sets, so ``considered`` is 0 and
    ``unpruned`` None."""
    started = time.perf_counter()
    trial = simulate_collaborative(s, level, seed, parameters)
    elapsed = time.perf_counter() - started
    return {
        "success": int(trial.success),
        "steps": int(trial.steps),
        "completion_step": trial.completion_step,
        "wall_time": elapsed,
        "decision_ms": 1e3 * elapsed / max(trial.steps, 1),
        "considered": 0.0,
        "unpruned": None,
        "trace": encode(collaborative_trace(s, trial)) if traces else None,
    }
