"""Observation events of a simulated mission: when they happen, what they do to the world,
what they teach and who observes them.

An :class:`EventRule` is an action model of the mA* family (an
:class:`~epistemica.del_.Observation` once its observers are known) plus what makes it
happen in the simulated world. Mission files declare rules in the spec language's action
syntax (``announces``, ``senses``, ``suggests``, ``full``/``partial`` observers with ``if``
conditions) with a ``when`` trigger and world effects; the library of
``epistemica/events.epi`` holds ``settle`` and ``complete``.

Triggers (``R`` a robot, ``G`` a goal, ``X`` either; names or parameters):

- ``step N``: at step ``N``;
- ``R settles at G``: every step ``R`` stands still (less than 5 cm moved) within the
  success radius of ``G``, its nearest goal;
- ``R reaches G``: the step ``R`` comes within the success radius of ``G``;
- ``R within D of X``: the step the distance from ``R`` to ``X`` drops to ``D`` m or less
  (never when the occurrence would reveal a closed goal: a closed goal, a task done, is
  not discovered);
- ``G is reached``: the first step a robot is within the success radius of the open goal
  ``G``; the robots there are ``reachers`` (in a collaborative mission, the step enough
  robots are there at once to do the task: :mod:`epistemica.sim.kinds.collaborative`);
- ``R heads to G``: every step ``R`` moves towards ``G``, the place its policy steers it to
  (a simulator that knows no such place, as :func:`~epistemica.sim.engine.simulate`, never fires
  it).

World effects: ``closes G`` (``G`` no longer counts for success and is no longer
discovered), ``opens G``. Content, as in the spec language's observability blocks: ``pre F``
(every observer learns ``F``), ``announces F`` (full observers learn ``F``, partial ones
that it was announced or denied), ``senses F`` (full observers learn whether ``F``, a fact
about closed goals the simulator knows), ``suggests F`` (a soft fact, a radical upgrade),
``reveals G`` (full observers become aware of goal ``G``). Observer conditions are formulas
over the world as each candidate observer ``o`` perceives it: ``sees(X)`` (``X`` within
``o``'s sensing range; ``X`` may be ``reachers``), ``near(X, D)`` (``o`` within ``D`` m of
``X``) and ``sensor(range)``/``sensor(bearing)``; an observer named ``robots`` stands for
every robot.

Examples
--------
>>> from epistemica.del_ import parse_formula
>>> rule = EventRule(
...     "settle", (("r", "robots"), ("g", "goals")), Trigger("settles", "r", "g"),
...     suggests=parse_formula("assigned(r, g)"),
...     full=(ObserverRule("robots", parse_formula("sees(r)")),))
>>> str(bind(rule.suggests, {"r": "r2", "g": "g1"}))
'assigned(r2, g1)'
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.checker import propositional_truth
from epistemica.del_.language.formula import Atom, Formula, Top, map_atoms
from epistemica.del_.state import Observation
from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.worlds import closed_fact, goal_atoms

__all__ = [
    "STILL",
    "TRIGGERS",
    "EventRule",
    "Firing",
    "ObserverRule",
    "Trigger",
    "World",
    "bind",
    "expand",
    "fire",
    "firings",
    "observer_indices",
]

#: Trigger kinds and what they name: ``(robot, target, value)`` slots each one uses.
TRIGGERS = {
    "step": (False, False, True),
    "settles": (True, True, False),
    "reaches": (True, True, False),
    "within": (True, True, True),
    "reached": (False, True, False),
    "heads": (True, True, False),
}
#: Observer predicates, with their arities.
PREDICATES = {"sees": 1, "near": 2, "sensor": 1}
#: Distance (m) below which a robot that moved counts as standing still.
STILL = 0.05


@dataclass(frozen=True)
class Trigger:
    """What makes an event happen (see the module notes)."""

    kind: str
    robot: str | None = None
    target: str | None = None
    value: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in TRIGGERS:
            raise InvalidArgumentError(
                f"unknown trigger {self.kind!r}", hint=f"one of {', '.join(TRIGGERS)}"
            )


@dataclass(frozen=True)
class ObserverRule:
    """``who`` (a robot, a parameter or ``robots``) observes when ``condition`` holds."""

    who: str
    condition: Formula = field(default_factory=Top)


@dataclass(frozen=True)
class EventRule:
    """An observation event of a mission: trigger, world effects, content, observers."""

    name: str
    parameters: tuple[tuple[str, str], ...]
    trigger: Trigger
    closes: tuple[str, ...] = ()
    opens: tuple[str, ...] = ()
    pre: Formula | None = None
    announces: Formula | None = None
    senses: Formula | None = None
    suggests: Formula | None = None
    reveals: tuple[str, ...] = ()
    full: tuple[ObserverRule, ...] = ()
    partial: tuple[ObserverRule, ...] = ()


class World(NamedTuple):
    """The simulated world at one step, as event rules read it."""

    step: int
    poses: np.ndarray  # (n, 3) true poses now
    previous: np.ndarray | None  # (n, 3) true poses one step before (None at the start)
    goals: np.ndarray  # (m, 2)
    open: np.ndarray  # (m,) goals that count (not closed)
    reached: np.ndarray  # (m,) goals first reached now
    visible: np.ndarray  # (n, n) j within i's sensing range
    sensing_range: float
    success_radius: float
    sensors: tuple[str, ...]
    robots: tuple[str, ...]
    goal_names: tuple[str, ...]
    heading: np.ndarray | None = None  # (n,) goal each robot steers to, -1 none (optional)


class Firing(NamedTuple):
    """One occurrence of a rule: its binding, the observation and the world effects."""

    binding: dict[str, str]
    observation: Observation
    closes: tuple[int, ...]
    opens: tuple[int, ...]


def bind(formula: Formula | None, env: Mapping[str, str]) -> Formula | None:
    """``formula`` with every parameter of ``env`` replaced where it names a robot or a
    goal (an atom's argument, or an atom of its own)."""
    if formula is None or not env:
        return formula

    def replace(atom: Atom) -> Formula:
        if not atom.args and atom.name in env:
            return Atom(env[atom.name])
        return Atom(atom.name, tuple(env.get(str(a), str(a)) for a in atom.args))

    return map_atoms(formula, replace)


def expand(formula: Formula | None, robots: Sequence[str]) -> Formula | None:
    """``formula`` with each ``closed(G)`` replaced by "no robot goes to ``G``"."""
    if formula is None:
        return None

    def replace(atom: Atom) -> Formula:
        if atom.name == "closed" and len(atom.args) == 1:
            return closed_fact(robots, str(atom.args[0]))
        return atom

    return map_atoms(formula, replace)


def _position(world: World, name: str) -> np.ndarray:
    if name in world.robots:
        return world.poses[world.robots.index(name), :2]
    return world.goals[world.goal_names.index(name)]


def _bindings(rule: EventRule, world: World) -> list[tuple[dict, np.ndarray | None]]:
    """The parameter bindings for which the trigger holds now, each with the robots that
    reached the goal (for ``G is reached``; else None). Vectorised over the candidates."""
    t, names = rule.trigger, dict(rule.parameters)
    if t.kind == "step":
        return [({}, None)] if world.step == int(t.value) else []
    goals = world.goal_names
    if t.kind == "reached":
        near = distances(world.poses, world.goals) <= world.success_radius  # (n, m)
        out = []
        for j in np.flatnonzero(world.reached):
            if t.target in names or goals[j] == t.target:
                binding = {t.target: goals[j]} if t.target in names else {}
                out.append((binding, near[:, j]))
        return out
    robots = world.robots
    places = _places(world, t.target, names)
    spots = np.array([_position(world, x) for x in places]).reshape(-1, 2)
    now = distances(world.poses, spots)  # (n, targets)
    if t.kind == "heads":
        hits = _heading_hits(world, places)
    elif t.kind == "settles":
        hits = np.zeros_like(now, dtype=bool)
        if world.previous is not None:
            moved = np.hypot(*(world.poses[:, :2] - world.previous[:, :2]).T)
            d = distances(world.poses, world.goals)
            nearest = np.argmin(d, axis=1)
            settled = (moved < STILL) & (d[np.arange(len(robots)), nearest] <= world.success_radius)
            column = {g: k for k, g in enumerate(places)}
            for i in np.flatnonzero(settled):
                k = column.get(goals[nearest[i]])
                if k is not None:
                    hits[i, k] = True
    else:
        radius = world.success_radius if t.kind == "reaches" else float(t.value)
        before = np.inf if world.previous is None else distances(world.previous, spots)
        hits = (now <= radius) & (before > radius)
    if t.robot not in names:
        keep = np.zeros(len(robots), dtype=bool)
        keep[robots.index(t.robot)] = True
        hits &= keep[:, None]
    out = []
    for i, k in zip(*np.nonzero(hits), strict=True):
        binding = {t.robot: robots[i], t.target: places[k]}
        out.append(({key: v for key, v in binding.items() if key in names}, None))
    return out


def _heading_hits(world: World, places: Sequence[str]) -> np.ndarray:
    """``(n, targets)``: robot ``i`` moved (at least :data:`STILL`) towards goal ``k``."""
    hits = np.zeros((len(world.robots), len(places)), dtype=bool)
    if world.heading is None or world.previous is None:
        return hits
    moved = np.hypot(*(world.poses[:, :2] - world.previous[:, :2]).T) >= STILL
    for k, name in enumerate(places):
        if name in world.goal_names:
            hits[:, k] = moved & (world.heading == world.goal_names.index(name))
    return hits


def _places(world: World, slot: str, names: Mapping[str, str]) -> list[str]:
    """The goals or robots a trigger's target may stand for."""
    if slot not in names:
        return [slot]
    if names[slot] == "robots":
        return list(world.robots)
    return list(world.goal_names)


def _observers(
    rules: Sequence[ObserverRule], env: Mapping[str, str], world: World, reachers
) -> np.ndarray:
    """``(n,)`` the robots that observe by one of ``rules`` (conditions per observer)."""
    n = len(world.robots)
    d_robots = distances(world.poses, world.poses)
    d_goals = distances(world.poses, world.goals)

    def distance_to(name: str) -> np.ndarray:
        if name in world.robots:
            return d_robots[:, world.robots.index(name)]
        return d_goals[:, world.goal_names.index(name)]

    mask = np.zeros(n, dtype=bool)
    for rule in rules:
        atoms = {a.key: a for a in rule.condition.atoms()}

        def atom_mask(key: str, atoms=atoms) -> np.ndarray:
            atom = atoms[key]
            args = [env.get(str(a), str(a)) for a in atom.args]
            if atom.name == "sees" and args[0] == "reachers":
                who = np.zeros(n, dtype=bool) if reachers is None else reachers
                return (world.visible & who[None, :]).any(axis=1)
            if atom.name == "sees":
                return distance_to(args[0]) <= world.sensing_range
            if atom.name == "near":
                return distance_to(args[0]) <= float(args[1])
            return np.array([s == args[0] for s in world.sensors])

        holds = propositional_truth(rule.condition, n, atom_mask)
        who = env.get(rule.who, rule.who)
        if who == "robots":
            mask |= holds
        else:
            i = world.robots.index(who)
            mask[i] |= holds[i]
    return mask


def _outcome(fact: Formula | None, world: World) -> bool | None:
    """The truth of a sensed fact in the simulated world (facts about closed goals)."""
    if fact is None:
        return None

    def atom_mask(key: str) -> np.ndarray:
        atom = next(a for a in fact.atoms() if a.key == key)
        if atom.name != "closed" or len(atom.args) != 1:
            raise InvalidArgumentError(
                f"a robot cannot sense {key}: the simulator knows which goals are closed, "
                "not where teammates will go",
                hint="sense closed(GOAL) facts; announce or suggest facts about assignments",
            )
        return np.array([not world.open[world.goal_names.index(str(atom.args[0]))]])

    return bool(propositional_truth(fact, 1, atom_mask)[0])


def fire(rule: EventRule, world: World) -> list[Firing]:
    """Every occurrence of ``rule`` at this step of ``world``."""
    robots, out = world.robots, []
    for env, reachers in _bindings(rule, world):
        full = _observers(rule.full, env, world, reachers)
        partial = _observers(rule.partial, env, world, reachers) & ~full
        # An announcement is sensing whose outcome the event asserts: full observers learn
        # the fact, partial ones that it was announced or denied.
        sensed = bind(rule.senses, env)
        outcome = _outcome(sensed, world)
        if rule.announces is not None:
            sensed, outcome = bind(rule.announces, env), True
        revealed = [goal_atoms(robots, env.get(g, g)) for g in rule.reveals]
        opened = [env.get(g, g) for g in rule.opens]
        observation = Observation(
            rule.name,
            full={robots[i] for i in np.flatnonzero(full)},
            partial={robots[i] for i in np.flatnonzero(partial)},
            pre=expand(bind(rule.pre, env), robots),
            senses=expand(sensed, robots),
            outcome=outcome,
            suggests=expand(bind(rule.suggests, env), robots),
            aware=frozenset().union(*revealed),
            args=tuple(env.get(p, "") for p, _ in rule.parameters),
            withdraws=tuple(closed_fact(robots, g) for g in opened),  # seen closed before
        )
        closes = tuple(world.goal_names.index(env.get(g, g)) for g in rule.closes)
        opens = tuple(world.goal_names.index(env.get(g, g)) for g in rule.opens)
        if rule.trigger.kind == "within" and _reveals_closed(rule, env, world, opens):
            continue
        out.append(Firing(dict(env), observation, closes, opens))
    return out


def _reveals_closed(rule: EventRule, env: Mapping[str, str], world: World, opens) -> bool:
    """Whether an occurrence reveals a goal that is closed and stays closed."""
    for g in rule.reveals:
        k = world.goal_names.index(env.get(g, g))
        if not world.open[k] and k not in opens:
            return True
    return False


def firings(rules: Sequence[EventRule], world: World, arrivals: bool) -> list[tuple]:
    """``(rule, firing)`` for every occurrence of ``rules`` at this step of ``world``: the
    arrival rules (``G is reached``, fired right after the robots move) when ``arrivals``,
    the others (fired when the robots perceive) otherwise; rules in order."""
    return [
        (rule, firing)
        for rule in rules
        if (rule.trigger.kind == "reached") == arrivals
        for firing in fire(rule, world)
    ]


def observer_indices(observation: Observation, robots: Sequence[str]) -> tuple[int, ...]:
    """Indices of the robots that observe ``observation`` (fully or partially)."""
    names = observation.full | observation.partial
    return tuple(i for i, r in enumerate(robots) if r in names)
