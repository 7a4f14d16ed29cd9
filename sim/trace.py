"""A trial's per-step record as a compact, versioned document (``epistemica-trace`` v1).

What a figure, a browser replay or an audit needs of a trial, and nothing of the process
that ran it: the world (names, goals, sensors, ranges), the true poses step by step, each
robot's belief about its own goal, the sizes of its configuration sets (its own, the ones
it models each teammate keeping, before pruning), its focal configuration, and every
observation event with its observers. :func:`trial_trace` builds it from a
:class:`~epistemica.sim.Scenario` and a :class:`~epistemica.sim.Trial`; :func:`encode`
and :func:`decode` turn it into bytes (JSON, zlib) and back.

Fields (arrays as nested lists; ``T`` steps, ``n`` robots, ``m`` goals):

==================  ==========================================================================
``format``          ``"epistemica-trace"``
``version``         ``1``
``robots``          ``n`` names; ``goals``: ``m`` names
``goal_positions``  ``(m, 2)`` metres
``workspace``       side of the workspace (m); ``sensing_range``: m or ``null`` (unlimited)
``success_radius``  m; ``sensors``: ``n`` sensor types; ``policies``: ``n`` level names
``seed``            trial seed; ``success``, ``steps``
``poses``           ``(T + 1, n, 3)``: x, y (m, 2 decimals) and heading (rad)
``goal_belief``     ``(T, n, m)``: robot ``i``'s belief that goal ``g`` is its own (3 decimals)
``considered``      ``(T, n)``: configurations in robot ``i``'s own set
``unpruned``        ``(T, n)``: before pruning by what it observed
``modelled``        ``(T, n, n)``: the size of the set robot ``i`` models ``j`` keeping
``focal``           ``(T, n, n)``: the configuration robot ``i`` acted on (-1: none)
``estimates``       ``(T, n, n, 2)``: where robot ``i`` placed robot ``j`` (m, 1 decimal)
``events``          ``[step, name, [arguments], [observers]]``, robots and goals by index
==================  ==========================================================================

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> s = Scenario.paper("rendezvous", 2, 2, seed=0)
>>> trace = trial_trace(s, simulate(s, "convention", seed=0))
>>> trace["version"], len(trace["poses"]) == trace["steps"] + 1
(1, True)
>>> decode(encode(trace)) == trace
True
"""

from __future__ import annotations

import json
import zlib
from typing import Any

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.scenario import Scenario
from epistemica.sim.trial import Trial

__all__ = ["FORMAT", "VERSION", "decode", "encode", "trial_trace"]

FORMAT = "epistemica-trace"
VERSION = 1


def _rounded(array: np.ndarray, decimals: int) -> list:
    out = np.round(np.asarray(array, dtype=float), decimals)
    return np.where(np.isfinite(out), out, np.nan).tolist()


def trial_trace(scenario: Scenario, trial: Trial) -> dict[str, Any]:
    """The trace document of ``trial`` (a trial of ``scenario``)."""
    events = [
        [int(e[0]), str(e[1]), [int(a) for a in e[2:-1]], [int(o) for o in e[-1]]]
        for e in trial.events
    ]
    return {
        "format": FORMAT,
        "version": VERSION,
        "robots": list(scenario.robot_names),
        "goals": list(scenario.goal_names),
        "goal_positions": _rounded(scenario.goals, 2),
        "workspace": float(scenario.workspace),
        "sensing_range": scenario.sensing_range,
        "success_radius": float(scenario.success_radius),
        "sensors": list(scenario.sensors),
        "policies": list(trial.policies),
        "seed": int(trial.seed),
        "success": bool(trial.success),
        "steps": int(trial.steps),
        "poses": _rounded(trial.trajectory, 2),
        "goal_belief": _rounded(trial.goal_belief, 3),
        "considered": np.asarray(trial.considered).tolist(),
        "unpruned": np.asarray(trial.unpruned).tolist(),
        "modelled": np.asarray(trial.modelled).tolist(),
        "focal": np.asarray(trial.focal).tolist(),
        "estimates": _rounded(trial.estimates, 1),
        "events": events,
    }


def encode(trace: dict[str, Any]) -> bytes:
    """The trace as zlib-compressed JSON (NaN written as ``null``)."""
    text = json.dumps(trace, separators=(",", ":"), allow_nan=True).replace("NaN", "null")
    return zlib.compress(text.encode("utf-8"), 9)


def decode(blob: bytes) -> dict[str, Any]:
    """The trace document of :func:`encode`'s bytes; a clear error for anything else."""
    try:
        trace = json.loads(zlib.decompress(blob).decode("utf-8"))
    except (zlib.error, UnicodeDecodeError, json.JSONDecodeError, TypeError) as exc:
        raise InvalidArgumentError(
            f"not an epistemica trace ({exc})", hint="traces are written by epistemica sweeps"
        ) from None
    if not isinstance(trace, dict) or trace.get("format") != FORMAT:
        raise InvalidArgumentError("not an epistemica trace", hint="no 'format' field")
    if trace.get("version") != VERSION:
        raise InvalidArgumentError(
            f"trace version {trace.get('version')!r}, this epistemica reads {VERSION}",
            hint="re-run the trial with this version",
        )
    return trace
