"""Which configurations a robot reasons over at a step, and which of them its teammates do.

:class:`ConfigurationSets` chooses, for one robot, the goals it reasons about and the valid
configurations over them: every valid configuration when the goals it knows allow it and
their number stays below ``prune_from``; the plausible ones (within a margin of the least
total distance, :func:`epistemica.aif.prior.plausible_configurations`) beyond; for
multitask, the allocations of the tasks the team works on now
(:mod:`~epistemica.sim.policies.tasking`). :func:`nested_sets` restricts that table to what the
robot believes possible and, per modelled teammate, to what the robot knows that teammate
keeps (docs/aif.md, "Nested configuration sets"); :func:`held_to` and :func:`known_slots`
adjust those sets for the planner (anchors, goals a teammate was not shown).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from epistemica.aif.configurations import (
    shared_configurations,
)
from epistemica.aif.evidence import perspective_sets
from epistemica.aif.perspective import perspectives
from epistemica.aif.prior import plausible_configurations
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.kinds.goal import ALLOCATION, CAPACITY
from epistemica.sim.policies.baselines import open_goals
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.tasking import select_tasks, task_slots

__all__ = ["Choice", "ConfigurationSets", "NestedSets", "held_to", "known_slots", "nested_sets"]


class Choice(NamedTuple):
    """The goals a robot reasons over (global indices) and a builder of the valid
    configurations over them (rows of indices into ``goals``); ``shared`` says whether the
    set depends only on the goals (a controller over it may be reused)."""

    goals: np.ndarray
    rows: Callable[[], np.ndarray] | None
    shared: bool = True


class ConfigurationSets:
    """The configuration sets of the robots of one trial."""

    def __init__(self, scenario: Scenario, parameters: ActiveParameters) -> None:
        self.scenario, self.parameters = scenario, parameters

    def choose(self, observations: Observations, robot: int) -> Choice:
        """The goals ``robot`` reasons over and their valid configurations."""
        s, n = self.scenario, self.scenario.n_robots
        known = open_goals(s, observations, robot)
        if not self.parameters.pruning:  # the ablation: tasks seen done are not pruned
            known = np.flatnonzero(observations.known_goals[robot])
        kind = s.kind
        if kind.tasks:
            return self._tasks(observations, robot, known)
        large = self.parameters.prune_from
        if known.size == s.n_goals:
            if kind.count(n, s.n_goals, s.capacities) >= large:
                return self._plausible(observations, robot, known, kind, s.capacities)
            return Choice(known, s.configurations)
        if s.valid is None and not kind.capacities:
            # The valid configurations over the known goals, enumerated directly (the same
            # rows, in the same order, as filtering the whole set).
            total = kind.count(n, known.size) if known.size else 0
            if total == 0:
                return Choice(known[:0], None)  # too few goals known
            if total >= large:
                return self._plausible(observations, robot, known, kind, None)
            return Choice(known, lambda: kind.configurations(n, known.size))
        rows = s.configurations()
        usable = np.isin(rows, known).all(axis=1)
        if not usable.any():  # too few goals known for any valid configuration
            return Choice(known[:0], None)
        remap = np.full(s.n_goals, -1)
        remap[known] = np.arange(known.size)
        return Choice(known, lambda: remap[rows[usable]])

    def _tasks(self, observations: Observations, robot: int, known: np.ndarray) -> Choice:
        s, n = self.scenario, self.scenario.n_robots
        slots = task_slots(select_tasks(observations.poses[robot], s.goals, known), n)
        # Fewer open tasks than robots: each task takes as many robots as it has slots.
        tasks, copies = np.unique(slots, return_counts=True)
        kind, caps = (ALLOCATION, None) if len(tasks) == n else (CAPACITY, copies)
        if len(tasks) and kind.count(n, len(tasks), caps) >= self.parameters.prune_from:
            return self._plausible(observations, robot, tasks, kind, caps)
        if caps is None:  # one task each: the allocations, shared across robots and steps
            return Choice(tasks, lambda: shared_configurations(kind.name, n, n))
        return Choice(tasks, lambda: kind.configurations(n, len(tasks), caps))

    def _plausible(self, observations, robot, goals, kind, capacities) -> Choice:
        """The plausible configurations of this robot at this step (not shared)."""
        view = observations.poses[robot, :, :2]
        cost = np.hypot(*(view[:, None, :] - self.scenario.goals[goals][None]).transpose(2, 0, 1))
        scale = 1.0 if self.parameters.prior_scale is None else self.parameters.prior_scale
        within = scale * (len(view) + self.parameters.plausible_margin)
        rows = plausible_configurations(cost, kind.name, capacities, within)
        return Choice(goals, lambda: rows, shared=False)


class NestedSets(NamedTuple):
    """A robot's own set and, per modelled perspective, the set it models, as masks over
    one table of configurations; ``pairs[j]`` is ``B_ij`` (what the robot knows teammate
    ``j`` keeps) and ``triples[j, k]`` is ``B_ijk`` (order 3), for anticipation."""

    own: np.ndarray
    modelled: list[np.ndarray]
    pairs: dict[int, np.ndarray]
    triples: dict[tuple[int, int], np.ndarray]

    @property
    def union(self) -> np.ndarray:
        """Every configuration some perspective keeps (the controller's table)."""
        return np.logical_or.reduce([self.own, *self.modelled])


def nested_sets(
    knowledge: TeamKnowledge,
    sensors,
    robot: int,
    order: int,
    table: np.ndarray,
    nested: bool = True,
    revision: str = "recency",
) -> NestedSets:
    """The robot's ``B`` set over ``table`` (global goal indices) and, for each perspective
    it models (:func:`epistemica.aif.perspective.perspectives`), the union of the sets of
    the chains that end at that teammate. ``nested=False`` is the ablation: every modelled
    perspective gets the robot's own set. ``revision`` orders settle suggestions
    (:meth:`TeamKnowledge.possible_many`)."""
    chains = perspective_sets(sensors, robot, order)
    n = len(sensors)
    pairs = [(robot, j) for j in range(n) if j != robot] if order >= 2 else []
    triples = [(robot, j, k) for _, j in pairs for k in range(n) if k != j] if order >= 3 else []
    # Chains that saw the same events keep the same set: computed once per signature.
    every = [(robot,)] + [c for level in chains[2:] for c in level] + pairs + triples
    kept = dict(zip(every, knowledge.possible_many(every, table, revision), strict=True))
    own = kept[(robot,)]
    modelled = []
    for view in perspectives(sensors, robot, order)[1:]:
        if not nested:
            modelled.append(own)
            continue
        level = 2 if view.order == order - 1 else 3
        mask = np.zeros(len(table), dtype=bool)
        for chain in chains[level]:
            if chain[-1] == view.agent:
                mask |= kept[chain]
        modelled.append(mask)
    if not nested:  # the ablation: every teammate keeps what the robot keeps
        return NestedSets(own, modelled, {j: own for _, j in pairs}, {})
    return NestedSets(
        own,
        modelled,
        {j: kept[(robot, j)] for _, j in pairs},
        {(j, k): kept[(robot, j, k)] for _, j, k in triples},
    )


def held_to(sets: NestedSets, table: np.ndarray, anchors: dict[int, int]) -> NestedSets:
    """``sets`` with every chain's set held to the configurations that put each anchor
    (teammate -> goal, scenario indices of ``table``, ``(k, n)``) at its goal: its set's
    part there, or all of them where its set has none (an anchor never leaves, so a set
    that excludes its goal cannot form). Unchanged when no configuration holds them all.

    Examples
    --------
    >>> table = np.array([[0, 0, 0], [1, 1, 1]])       # rendezvous at goal 0 or goal 1
    >>> newest = np.array([False, True])               # the newest settles: goal 1
    >>> sets = NestedSets(newest, [newest], {1: newest}, {})
    >>> held = held_to(sets, table, {2: 0})            # robot 2 stands at goal 0 for good
    >>> held.own.tolist(), held.pairs[1].tolist(), held.union.tolist()
    ([True, False], [True, False], [True, True])
    """
    if not anchors:  # every plan of every robot passes here: nothing to build
        return sets
    there = np.ones(len(table), dtype=bool)
    for teammate, goal in anchors.items():
        there &= table[:, teammate] == goal
    if not there.any():
        return sets

    def hold(mask: np.ndarray) -> np.ndarray:
        both = mask & there
        return both if both.any() else there

    return NestedSets(
        hold(sets.own),
        sets.modelled,  # the table keeps every configuration some perspective keeps
        {j: hold(mask) for j, mask in sets.pairs.items()},
        {chain: hold(mask) for chain, mask in sets.triples.items()},
    )


def known_slots(sets: NestedSets, knowledge: TeamKnowledge, robot: int, table: np.ndarray,
                near: np.ndarray | None = None) -> NestedSets:  # fmt: skip
    """``sets`` with each chain that keeps no configuration, although its last robot knows
    an open goal of ``table`` (too few for a configuration), held to the configurations that
    put that robot at a goal it may know (``plan_few``): not at one the chain knows it was
    not shown (:meth:`TeamKnowledge.unshown`), which an empty set, restricting nothing,
    allows. Other chains, and chains with no such goal in ``table`` (``(k, n)``, scenario
    indices) or only such goals, are unchanged. ``near`` (``(n, m)`` booleans): where the
    robot places a teammate within discovery range of a goal, it may have been shown it.

    Examples
    --------
    >>> from epistemica.del_.state import Observation
    >>> from epistemica.sim.engine.knowledge import TeamKnowledge
    >>> knowledge = TeamKnowledge(["r1", "r2"], ["g1", "g2"], [[True, False], [True, False]])
    >>> opened = Observation("opens", full={"r2"}, aware=knowledge._goal_atoms[1],
    ...                      withdraws=(knowledge.closed[1],))
    >>> knowledge.observe(opened)                      # g2 opens, shown to r2 alone
    True
    >>> table = np.array([[0, 1], [1, 0]])             # an allocation of two
    >>> sets = NestedSets(np.array([True, True]), [], {0: np.zeros(2, bool)}, {})
    >>> known_slots(sets, knowledge, 1, table).pairs[0].tolist()  # r1 at g1
    [True, False]
    """

    def fill(chain: tuple[int, ...], mask: np.ndarray) -> np.ndarray:
        known = knowledge.knows_goals(chain) & ~knowledge.knows_done(chain)
        if mask.any() or not known[table[:, chain[-1]]].any():
            return mask  # one that knows no open goal sweeps: it ends where it finds the team
        unshown = knowledge.unshown(chain)
        if near is not None:
            unshown &= ~near[chain[-1]]
        slot = ~unshown[table[:, chain[-1]]]
        return slot if slot.any() and not slot.all() else mask

    return NestedSets(
        sets.own,
        sets.modelled,
        {j: fill((robot, j), mask) for j, mask in sets.pairs.items()},
        {(j, k): fill((robot, j, k), mask) for (j, k), mask in sets.triples.items()},
    )
