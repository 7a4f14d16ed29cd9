"""A trial's per-step record as a compact, versioned document (``epistemica-trace`` v2).

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
``version``         ``2`` (version 1, read too, gave event arguments as indices)
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
``events``          ``[step, name, [arguments], [observers]]``: arguments by name (the
                    robots and goals the event was about), observers by index
``types``           (only where robots kept teammate models) the behaviour library's names
``teammate_types``  ``(T, n, n, len(types))``: robot ``i``'s posterior over robot ``j``'s
                    behaviour when it decided (2 decimals; ``null`` where it kept none)
==================  ==========================================================================

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> s = Scenario.paper("rendezvous", 2, 2, seed=0)
>>> trace = trial_trace(s, simulate(s, "convention", seed=0))
>>> trace["version"], len(trace["poses"]) == trace["steps"] + 1
(2, True)
>>> decode(encode(trace)) == trace
True
"""

from __future__ import annotations

import json
import zlib
from typing import Any

import numpy as np

from epistemica.aif.teammates import TYPES
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.scenario import Scenario
from epistemica.sim.trial import Trial

__all__ = ["FORMAT", "MAX_TRACE_BYTES", "READABLE", "VERSION", "decode", "encode", "trial_trace"]

#: The largest trace document read, inflated (a stored trace is about 2 kB compressed;
#: the longest shipped trial's document is well under 1 MB; inflating 16 MiB takes tens of ms).
MAX_TRACE_BYTES = 16 << 20

FORMAT = "epistemica-trace"
VERSION = 2
#: The versions :func:`decode` reads.
READABLE = (1, 2)


def _rounded(array: np.ndarray, decimals: int) -> list:
    out = np.round(np.asarray(array, dtype=float), decimals)
    return np.where(np.isfinite(out), out, np.nan).tolist()


def trial_trace(scenario: Scenario, trial: Trial) -> dict[str, Any]:
    """The trace document of ``trial`` (a trial of ``scenario``)."""
    named = _argument_namer(scenario)
    events = [
        [int(e[0]), str(e[1]), named(e[1], e[2:-1]), [int(o) for o in e[-1]]] for e in trial.events
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
        **_teammate_types(trial),
    }


def _teammate_types(trial: Trial) -> dict[str, Any]:
    if trial.teammate_types is None:
        return {}
    return {"types": list(TYPES), "teammate_types": _rounded(trial.teammate_types, 2)}


def _argument_namer(scenario: Scenario):
    """A function from an event's rule name and argument indices to the arguments' names (a
    robot's or a goal's, as the rule's parameter says; an unbound ``-1`` is ``""``)."""
    kinds = {r.name: [kind for _, kind in r.parameters] for r in scenario.events}
    names = {"robots": scenario.robot_names, "goals": scenario.goal_names}

    def named(rule: str, indices) -> list[str]:
        return [
            names[kind][int(i)] if int(i) >= 0 and kind in names else ""
            for kind, i in zip(kinds.get(rule, []), indices, strict=False)
        ]

    return named


def encode(trace: dict[str, Any]) -> bytes:
    """The trace as zlib-compressed JSON (NaN written as ``null``)."""
    text = json.dumps(trace, separators=(",", ":"), allow_nan=True).replace("NaN", "null")
    return zlib.compress(text.encode("utf-8"), 9)


def decode(blob: bytes) -> dict[str, Any]:
    """The trace document of :func:`encode`'s bytes; a clear error for anything else,
    a compressed blob that inflates beyond :data:`MAX_TRACE_BYTES` included (never
    inflated further, so a decompression bomb costs no more than that)."""
    try:
        inflater = zlib.decompressobj()
        text = inflater.decompress(blob, MAX_TRACE_BYTES)
        whole = not inflater.unconsumed_tail
        trace = json.loads(text.decode("utf-8")) if whole else None
    except (zlib.error, UnicodeDecodeError, ValueError, TypeError, RecursionError) as exc:
        raise InvalidArgumentError(
            f"not an epistemica trace ({exc})", hint="traces are written by epistemica sweeps"
        ) from None
    if not whole:
        raise InvalidArgumentError(
            f"the trace inflates beyond the limit of {MAX_TRACE_BYTES:,} bytes",
            hint="a stored trace is a few kB; this one is damaged or hostile",
        )
    if not isinstance(trace, dict) or trace.get("format") != FORMAT:
        raise InvalidArgumentError("not an epistemica trace", hint="no 'format' field")
    if trace.get("version") not in READABLE:
        raise InvalidArgumentError(
            f"trace version {trace.get('version')!r}, this epistemica reads "
            + ", ".join(map(str, READABLE)),
            hint="re-run the trial with this version",
        )
    return trace
