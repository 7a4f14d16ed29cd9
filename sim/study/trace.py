"""A trial's per-step record as a compact, versioned document (``epistemica-trace`` v3).

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
``version``         ``3`` (1 and 2 read too: version 1 gave event arguments as indices,
                    version 2 named a joint trial's ``tasks_known`` ``knows``)
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
``knows``           (only where some goal was unknown to some robot) ``[step, i, j, g, known,
                    how]`` for each change of "robot ``i`` takes robot ``j`` to know of goal
                    ``g``" (``i == j``: its own knowledge), step 0 listing what is known at
                    the start; ``how``: ``"start"``, the event's name, ``"seen"`` (within
                    discovery range) or ``"inferred"``
``closed``          (only where some goal was closed) ``[step, g, closed]`` for each change,
                    step 0 listing the goals closed at the start
``obstacles``       (only where there are obstacles) polygons, ``[[x, y], ...]`` each (m)
``discovery_range`` (only where set) m
==================  ==========================================================================

A trial of a joint (collaborative) mission carries ``kind: "collaborative"`` and, in place
of beliefs and configuration sets, its task ledger: ``needs`` (robots per task),
``tasks_done`` (``m``: the step each task was done, -1 never), ``steer_to`` (``(T, n)``: the
task each robot headed to, -1 exploring, -2 fetching a teammate, -3 waiting),
``tasks_known`` (``(T, n, m)``: 1 where robot ``i`` knew of task ``t`` when it decided) and
``aware_since`` (``(n, n, m)``: the first step robot ``i`` knew that robot ``j`` knows of
task ``t``, -1 never); its events name their arguments as the rule bound them. Version 2
wrote ``tasks_known`` as ``knows``, the name goal traces give their change list:
:func:`upgraded` (which :func:`decode` applies) renames it.

Every field from ``knows`` on is optional: traces without them (written before they were
recorded, or of trials where they are empty) read as they did.

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> s = Scenario.paper("rendezvous", 2, 2, seed=0)
>>> trace = trial_trace(s, simulate(s, "convention", seed=0))
>>> trace["version"], len(trace["poses"]) == trace["steps"] + 1
(3, True)
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
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.trial import Trial
from epistemica.sim.kinds.collaborative import CollaborativeScenario

__all__ = [
    "FORMAT",
    "MAX_TRACE_BYTES",
    "READABLE",
    "VERSION",
    "check_blob_size",
    "decode",
    "encode",
    "known_goals",
    "task_learning",
    "trial_trace",
    "upgraded",
]

#: The largest trace document read, inflated (a stored trace is about 2 kB compressed;
#: the longest shipped trial's document is well under 1 MB; inflating 16 MiB takes tens of ms).
MAX_TRACE_BYTES = 16 << 20

FORMAT = "epistemica-trace"
VERSION = 3
#: The versions :func:`decode` reads.
READABLE = (1, 2, 3)


def _rounded(array: np.ndarray, decimals: int) -> list:
    out = np.round(np.asarray(array, dtype=float), decimals)
    return np.where(np.isfinite(out), out, np.nan).tolist()


def trial_trace(scenario: Scenario | CollaborativeScenario, trial: Trial) -> dict[str, Any]:
    """The trace document of ``trial`` (a trial of ``scenario``)."""
    if scenario.kind.joint:
        return _joint_trace(scenario, trial)
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
        **_knowledge(scenario, trial, events),
    }


def _joint_trace(s: CollaborativeScenario, trial: Trial) -> dict[str, Any]:
    """The trace of a joint trial: the shared fields and the task ledger."""
    events = [
        [int(step), str(name), [str(a) for a in args], [int(o) for o in observers]]
        for step, name, args, observers in trial.events
    ]
    return {
        "format": FORMAT,
        "version": VERSION,
        "kind": s.kind.trace_kind,
        "robots": list(s.robot_names),
        "goals": list(s.task_names),
        "goal_positions": np.round(s.tasks, 2).tolist(),
        "needs": [int(k) for k in s.needs],
        "workspace": float(s.workspace),
        "sensing_range": float(s.sensing_range),
        "success_radius": float(s.completion_radius),
        "sensors": list(s.sensors),
        "policies": list(trial.policies),
        "seed": int(trial.seed),
        "success": bool(trial.success),
        "steps": int(trial.steps),
        "poses": np.round(trial.trajectory, 2).tolist(),
        "tasks_done": [int(d) for d in trial.tasks_done],
        "steer_to": np.asarray(trial.steer_to, dtype=int).tolist(),
        "tasks_known": np.asarray(trial.knows, dtype=int).tolist(),
        "aware_since": np.asarray(trial.aware_since, dtype=int).tolist(),
        "events": events,
    }


def _knowledge(scenario: Scenario, trial: Trial, events: list) -> dict[str, Any]:
    """The optional fields ``knows``, ``closed``, ``obstacles``, ``discovery_range``."""
    out: dict[str, Any] = {}
    if trial.known_goals is not None and len(trial.known_goals):
        out["knows"] = _knows(scenario, np.asarray(trial.known_goals, dtype=bool), events)
    closed = trial.closed_goals
    if closed is not None and np.asarray(closed).any():
        closed = np.asarray(closed, dtype=bool)
        start = [[0, int(g), 1] for g in np.flatnonzero(closed[0])]
        changed = np.argwhere(closed[1:] != closed[:-1])
        out["closed"] = start + [[int(t) + 1, int(g), int(closed[t + 1, g])] for t, g in changed]
    if scenario.obstacles:
        out["obstacles"] = [_rounded(p, 2) for p in scenario.obstacles]
    if scenario.discovery_range is not None:
        out["discovery_range"] = float(scenario.discovery_range)
    return out


def _knows(scenario: Scenario, known: np.ndarray, events: list) -> list:
    """``[step, i, j, g, known, how]`` for every change of ``known`` (``(T, n, n, m)``)."""
    told = scenario.known_goals
    goals = scenario.goal_names
    out = []
    for i, j, g in np.argwhere(known[0]):
        own = told is None or (told[i, g] if i == j else told[:, g].all())
        how = "start" if own else _how(0, i, j, goals[g], events)
        out.append([0, int(i), int(j), int(g), 1, how])
    for t, i, j, g in np.argwhere(known[1:] != known[:-1]):
        now = bool(known[t + 1, i, j, g])
        how = _how(int(t) + 1, i, j, goals[g], events) if now else ""
        out.append([int(t) + 1, int(i), int(j), int(g), int(now), how])
    return out


def _how(step: int, i: int, j: int, goal: str, events: list) -> str:
    """How robot ``i`` came to take ``j`` to know of ``goal`` at ``step``."""
    for e in events:
        if e[0] == step and i in e[3] and goal in e[2]:
            return e[1]
    return "seen" if i == j else "inferred"


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


def known_goals(trace: dict[str, Any]) -> np.ndarray | None:
    """``(T, n, n, m)`` booleans from a trace's ``knows`` changes: the goals robot ``i``
    takes robot ``j`` to know of at each step (its own on the diagonal); ``None`` for a
    trace without them (every goal common knowledge, or written before they were kept).

    Examples
    --------
    >>> k = known_goals({"steps": 3, "robots": ["a", "b"], "goals": ["x"],
    ...                  "knows": [[0, 0, 0, 0, 1, "start"], [2, 1, 1, 0, 1, "seen"]]})
    >>> k[:, 1, 1, 0].tolist(), k[:, 0, 0, 0].tolist()
    ([False, False, True], [True, True, True])
    """
    if "knows" not in trace:
        return None
    n, m = len(trace["robots"]), len(trace["goals"])
    steps = max(int(trace["steps"]), 1)
    changes = np.zeros((steps + 1, n, n, m), dtype=int)  # +1 set, -1 cleared, at the step
    for step, i, j, g, now, _ in trace["knows"]:
        changes[step, i, j, g] = 1 if now else -1
    known = np.zeros((n, n, m), dtype=bool)
    out = np.zeros((steps, n, n, m), dtype=bool)
    for t in range(steps):
        known = np.where(changes[t] > 0, True, np.where(changes[t] < 0, False, known))
        out[t] = known
    return out


def task_learning(trace: dict[str, Any]) -> list[list]:
    """How each robot of a joint trace came to know of each task it knew of: ``[step, i, t,
    how]`` in order of step, ``step`` being ``aware_since[i][i][t]`` and ``how`` the name of
    an event of that step robot ``i`` observed about task ``t``, else ``"seen"`` (the task
    within its sensing range then, to the trace's 2 decimals), else ``"told"`` (a level that
    shares news).

    Examples
    --------
    >>> trace = {"robots": ["a", "b"], "goals": ["t1"], "goal_positions": [[0.0, 0.0]],
    ...          "sensing_range": 5.0, "poses": [[[1.0, 0, 0], [20.0, 0, 0]]] * 4,
    ...          "aware_since": [[[0], [3]], [[3], [3]]], "events": [[3, "found", ["a", "t1"],
    ...          [1]]]}
    >>> task_learning(trace)
    [[0, 0, 0, 'seen'], [3, 1, 0, 'found']]
    """
    robots, tasks = trace["robots"], trace["goals"]
    since = np.asarray(trace["aware_since"], dtype=int).reshape(len(robots), len(robots), -1)
    places = np.asarray(trace["goal_positions"], dtype=float).reshape(-1, 2)
    poses = np.asarray(trace["poses"], dtype=float)
    reach = float(trace["sensing_range"]) + 0.02  # poses and places are rounded to 0.01 m
    out = []
    for i, t in np.argwhere(np.diagonal(since).T >= 0):
        step = int(since[i, i, t])
        told = [e[1] for e in trace["events"] if e[0] == step and i in e[3] and tasks[t] in e[2]]
        near = np.hypot(*(poses[min(step, len(poses) - 1), i, :2] - places[t])) <= reach
        out.append([step, int(i), int(t), told[0] if told else "seen" if near else "told"])
    return sorted(out)


def upgraded(trace: dict[str, Any]) -> dict[str, Any]:
    """``trace`` with today's field names (the same dict when nothing changes).

    A joint trace of version 2 or earlier (``kind`` set) kept the tasks each robot knew of
    under ``knows``, the key whose goal-trace meaning is a list of changes; it is moved to
    ``tasks_known``. The version is left as written.

    Examples
    --------
    >>> old = {"version": 2, "kind": "collaborative", "knows": [[[1, 0]]]}
    >>> sorted(upgraded(old)), upgraded(old)["tasks_known"]
    (['kind', 'tasks_known', 'version'], [[[1, 0]]])
    >>> goal = {"version": 2, "knows": [[0, 0, 0, 0, 1, "start"]]}
    >>> upgraded(goal) is goal
    True
    """
    if trace.get("kind") is None or "knows" not in trace or "tasks_known" in trace:
        return trace
    out = {key: value for key, value in trace.items() if key != "knows"}
    out["tasks_known"] = trace["knows"]
    return out


def encode(trace: dict[str, Any]) -> bytes:
    """The trace as zlib-compressed JSON (NaN written as ``null``)."""
    text = json.dumps(trace, separators=(",", ":"), allow_nan=True).replace("NaN", "null")
    return zlib.compress(text.encode("utf-8"), 9)


def check_blob_size(size: int | None, what: str = "the trace") -> None:
    """Refuse a stored trace of ``size`` bytes above :data:`MAX_TRACE_BYTES` before it is
    fetched (compressed, it is smaller than its document, which is bounded by the limit).

    Examples
    --------
    >>> check_blob_size(2_000)
    >>> try:
    ...     check_blob_size(MAX_TRACE_BYTES + 1, "r.sqlite: trial 'a'")
    ... except InvalidArgumentError as err:
    ...     print(err.message)
    r.sqlite: trial 'a' is 16,777,217 bytes, over the limit of 16,777,216
    """
    if size is not None and size > MAX_TRACE_BYTES:
        raise InvalidArgumentError(
            f"{what} is {size:,} bytes, over the limit of {MAX_TRACE_BYTES:,}",
            hint="a stored trace is a few kB; this one is damaged or hostile",
        )


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
    return upgraded(trace)
