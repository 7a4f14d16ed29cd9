"""What each robot knows, and what it knows of its teammates' knowledge: the simulator's
view of an :class:`epistemica.del_.EpistemicState`.

Every fact a robot learns during a trial (a goal exists, a task is done, a teammate has
settled at a goal, a fact it was told at the start, whatever a mission's own events teach)
comes from an observation event recorded in the logic layer's epistemic state, with its
observers. :class:`TeamKnowledge` names robots and goals by index, as the simulator does,
and answers the questions the policies ask: which configurations a chain of robots keeps
(its ``B`` set, :func:`epistemica.del_.state.explicit.belief_masks` over the
configurations as worlds of :mod:`epistemica.sim.engine.worlds`), which goals it knows of, which
teammates it saw settle where.

Examples
--------
Robot 0 sees task 2 completed, robot 1 does not:

>>> import numpy as np
>>> from epistemica.del_ import Observation
>>> k = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"])
>>> k.observe(Observation("complete", full={"r1"}, pre=k.closed[2]))
True
>>> rows = np.array([[0, 1], [0, 2], [2, 1]])
>>> k.possible((0,), rows).tolist()  # robot 0 prunes the rows that use task 2
[True, False, False]
>>> k.possible((0, 1), rows).tolist()  # ... and knows robot 1 has not
[True, True, True]
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from epistemica.del_.language.formula import Atom, Formula
from epistemica.del_.state import EpistemicState, Observation
from epistemica.del_.state.explicit import belief_masks
from epistemica.sim.engine.worlds import ConfigurationTable, closed_fact, goal_atoms

__all__ = ["PRIOR", "TeamKnowledge", "assignment", "initial_knowledge"]

#: The name of the observations of :meth:`TeamKnowledge.suggest` (a prior belief, no sighting).
PRIOR = "prior"

Chain = Sequence[int]


def assignment(fact: Formula | None) -> tuple[str, str] | None:
    """``(robot, goal)`` if ``fact`` is ``assigned(robot, goal)`` (what a settle suggests).

    Examples
    --------
    >>> assignment(Atom("assigned", ("r1", "g2")))
    ('r1', 'g2')
    >>> assignment(None) is None
    True
    """
    if isinstance(fact, Atom) and fact.name == "assigned" and len(fact.args) == 2:
        robot, goal = fact.args
        return str(robot), str(goal)
    return None


class TeamKnowledge:
    """The epistemic state of a team during one trial, robots and goals by index.

    Parameters
    ----------
    robots, goals : sequence of str
        Names, as the events' facts use them.
    known_goals : array_like, optional
        ``(n, m)`` booleans: robot ``i`` knows goal ``g`` at the start. Goals every robot
        knows are common knowledge; the others count as observed by each robot alone, and
        a robot conceives only of configurations over goals it knows of. Default: every
        goal, common knowledge.
    """

    def __init__(self, robots: Sequence[str], goals: Sequence[str], known_goals=None) -> None:
        self.robots, self.goals = tuple(robots), tuple(goals)
        self.n, self.m = len(self.robots), len(self.goals)
        tracked = set()
        if known_goals is not None:  # some goals unknown to some: awareness matters
            tracked = set().union(*(goal_atoms(self.robots, g) for g in self.goals))
        self.state = EpistemicState(self.robots, tracked=tracked)
        # Event content -> the (full observers, all observers) it was seen by: each
        # piece of evidence dates from its first sighting (:meth:`observe`).
        self._sightings: dict[tuple, list[tuple[frozenset, frozenset]]] = {}
        self._goal_atoms = tuple(goal_atoms(self.robots, g) for g in self.goals)
        #: ``closed[g]``: the fact "no robot goes to goal ``g``" (a task done, a goal closed).
        self.closed = tuple(closed_fact(self.robots, g) for g in self.goals)
        self._closed_goal = {fact: g for g, fact in enumerate(self.closed)}
        # chain -> knows_done / knows_goals, kept until the next observation is recorded
        self._done: dict[tuple, np.ndarray] = {}
        self._goals_known: dict[tuple, np.ndarray] = {}
        # (discover or notice, goal, observers) already reported: a repeat teaches nothing
        self._reported: set[tuple[str, int, frozenset]] = set()
        if known_goals is not None:
            known = np.asarray(known_goals, dtype=bool)
            for g in range(self.m):
                if known[:, g].all():
                    self.discover(g, np.ones(self.n, dtype=bool))
                else:
                    for i in np.flatnonzero(known[:, g]):
                        self.discover(g, np.arange(self.n) == i)

    # -- events ------------------------------------------------------------------------

    def observe(self, observation: Observation) -> bool:
        """Record an observation event; ``False`` if it taught nobody anything new.

        Evidence dates from its first sighting: an event whose observers had all seen
        the same event (fully, where they see it fully) is not recorded again, even after
        other evidence came in between (a robot still standing where it settled, or back
        at a goal it left, is not newer news). This is how every measured table was made;
        the logic layer's :meth:`~epistemica.del_.EpistemicState.observe` alone would
        record such a soft fact again, as the newest upgrade of a sequence.
        """
        full, seen = observation.full, observation.observers
        earlier = self._sightings.setdefault(observation.content, [])
        if any(full <= f and seen <= s for f, s in earlier):
            return False
        earlier.append((full, seen))
        if observation.withdraws:
            self._forget(observation)
        self._done.clear()  # what each chain knows may change
        self._goals_known.clear()
        return self.state.observe(observation)

    def _forget(self, observation: Observation) -> None:
        """After an ontic change, evidence of the facts it withdraws is news again: the
        sightings and reports of them are forgotten (a goal reopened may close again)."""
        void = set(observation.withdraws)
        for content in [c for c in self._sightings if void & {c[2], c[3]}]:
            del self._sightings[content]
        goals = {g for g, fact in enumerate(self.closed) if fact in void}
        self._unreport("notice", goals)

    def _unreport(self, what: str, goals: set[int]) -> None:
        """Forget the reports ``what`` of ``goals`` and their sightings: the next one is
        news."""
        self._reported = {r for r in self._reported if r[0] != what or r[1] not in goals}
        names = {(self.goals[g],) for g in goals}
        for content in [c for c in self._sightings if c[0] == what and c[1] in names]:
            del self._sightings[content]

    def discover(self, goal: int, observers) -> bool:
        """The observers (``n`` booleans) learn that ``goal`` exists, and who else did."""
        names = self._first_report("discover", goal, observers)
        if names is None:
            return False
        found = Observation(
            "discover",
            full=names,
            aware=self._goal_atoms[goal],
            args=(self.goals[goal],),
        )
        return self.observe(found)

    def notice_closed(self, goal: int, observers) -> bool:
        """The observers (``n`` booleans) see that ``goal`` is closed (a task done)."""
        names = self._first_report("notice", goal, observers)
        if names is None:
            return False
        seen = Observation("notice", full=names, pre=self.closed[goal], args=(self.goals[goal],))
        self._unreport("reopen", {goal})  # it may be seen reopened again
        return self.observe(seen)

    def notice_open(self, goal: int, observers) -> bool:
        """The observers (``n`` booleans) see that ``goal``, once known closed, is open:
        what they learnt of its closing no longer binds them."""
        names = self._first_report("reopen", goal, observers)
        if names is None:
            return False
        seen = Observation("reopen", full=names, args=(self.goals[goal],),
                           withdraws=(self.closed[goal],))  # fmt: skip
        return self.observe(seen)

    def _first_report(self, what: str, goal: int, observers) -> frozenset | None:
        """The observers' names, or None when they reported the same before (the same
        event seen by the same robots is no news: :meth:`observe` would refuse it)."""
        names = frozenset(self.robots[i] for i in np.flatnonzero(observers))
        key = (what, goal, names)
        if key in self._reported:
            return None
        self._reported.add(key)
        return names

    def tell(self, fact: Formula, observers) -> bool:
        """The observers (``n`` booleans) are told ``fact`` (and who else was)."""
        names = {self.robots[i] for i in np.flatnonzero(observers)}
        return self.observe(Observation("learns", full=names, pre=fact))

    def suggest(self, fact: Formula, observers) -> bool:
        """The observers (``n`` booleans) believe ``fact`` at the start, softly (a prior:
        a ``plausibility`` level of a mission); newer evidence that contradicts it wins."""
        names = {self.robots[i] for i in np.flatnonzero(observers)}
        return self.observe(Observation(PRIOR, full=names, suggests=fact))

    # -- queries ---------------------------------------------------------------------

    def constrains(self, chain: Chain) -> bool:
        """Whether an event's fact (hard or soft) reaches ``chain``."""
        return self.state.constrains(chain)

    def told(self, chain: Chain) -> bool:
        """Whether a hard fact (told, a task done, a goal closed, ...) reaches the chain."""
        return bool(self.state.hard(chain))

    def settled(self, chain: Chain) -> list[tuple[int, int]]:
        """``(robot, goal)`` of the suggestions ``assigned(ROBOT, GOAL)`` the whole chain
        saw (a teammate seen settled), newest first."""
        out = []
        events = self.state.observations
        for i in reversed(self.state.observed(chain, fully=True)):
            pair = assignment(events[i].suggests)
            if events[i].name != PRIOR and pair is not None:  # a prior is no sighting
                out.append((self.robots.index(pair[0]), self.goals.index(pair[1])))
        return out

    def knows_goals(self, chain: Chain) -> np.ndarray:
        """``(m,)`` the goals the chain knows of."""
        if not self.state.tracked:
            return np.ones(self.m, dtype=bool)
        chain = tuple(chain)
        known = self._goals_known.get(chain)
        if known is None:
            aware = self.state.aware(chain)
            known = np.array([atoms <= aware for atoms in self._goal_atoms], dtype=bool)
            self._goals_known[chain] = known
        return known.copy()

    def knows_done(self, chain: Chain) -> np.ndarray:
        """``(m,)`` the goals (tasks) the chain knows closed (done): the ``closed`` facts
        among the hard facts its group still holds (a goal seen reopened no longer
        counts), kept per chain until the next observation is recorded."""
        chain = tuple(chain)
        known = self._done.get(chain)
        if known is None:
            known = np.zeros(self.m, dtype=bool)
            for fact in self.state.hard(chain):
                g = self._closed_goal.get(fact, -1)
                if g >= 0:
                    known[g] = True
            self._done[chain] = known
        return known.copy()

    def unshown(self, chain: Chain) -> np.ndarray:
        """``(m,)`` the goals the chain knows its last robot was not shown: opened and
        revealed by an event the rest of the chain saw fully and that robot did not (a goal
        closed before it opened could not be discovered; only coming near it shows it).

        Examples
        --------
        >>> k = TeamKnowledge(["a", "b"], ["x", "y"], [[True, False], [True, False]])
        >>> k.observe(Observation("opens", full={"a"}, aware=k._goal_atoms[1],
        ...                       withdraws=(k.closed[1],)))
        True
        >>> k.unshown((0, 1)).tolist(), k.unshown((1, 0)).tolist()
        ([False, True], [False, False])
        """
        out = np.zeros(self.m, dtype=bool)
        if len(chain) < 2:
            return out
        agent, events = self.robots[chain[-1]], self.state.observations
        for i in self.state.observed(tuple(chain[:-1]), fully=True):
            if agent in events[i].full:
                continue
            for fact in events[i].withdraws:
                g = self._closed_goal.get(fact, -1)
                if g >= 0 and self._goal_atoms[g] <= events[i].aware:
                    out[g] = True
        return out & ~self.knows_goals(chain)

    def private_goals(self, robot: int) -> bool:
        """Whether ``robot`` knows of a goal that it does not know every teammate knows."""
        own = self.knows_goals((robot,))
        return any((own & ~self.knows_goals((robot, j))).any() for j in range(self.n) if j != robot)

    def signature(self, chain: Chain) -> tuple:
        """What the chain keeps, as a hashable key: chains with equal signatures keep the
        same configurations."""
        return self.state.signature(chain)

    def possible_many(
        self, chains: Sequence[Chain], rows: np.ndarray, revision: str = "recency"
    ) -> list:
        """:meth:`possible` for each chain, computed once per distinct signature
        (``revision``: how settle suggestions revise, ``"recency"`` or the ablation
        ``"primacy"``, :func:`epistemica.del_.state.state.soft_in_order`).

        Examples
        --------
        >>> k = TeamKnowledge(["a", "b", "c"], ["x", "y"])
        >>> a, b = k.possible_many([(0, 1), (1, 2)], np.array([[0, 0, 1]]))
        >>> a is b  # nothing was observed: one computation serves both chains
        True
        """
        table = ConfigurationTable(rows, self.robots, self.goals)
        return belief_masks(self.state, chains, table, revision)

    def possible(self, chain: Chain, rows: np.ndarray) -> np.ndarray:
        """Which configurations ``rows`` (``(k, n)`` global goal indices) the chain keeps:
        its ``B`` set (docs/language.md, "What a robot believes").

        A teammate's settle suggests its goal: the newest suggestion that leaves the chain
        a configuration wins (belief revision by recency).
        """
        return self.possible_many([chain], rows)[0]


def initial_knowledge(scenario) -> TeamKnowledge:
    """The team's knowledge at the start of a trial of ``scenario``: the goals each robot
    knows, the facts it was told and its prior beliefs (``Scenario.known_goals``,
    ``Scenario.told`` and ``Scenario.suggested``).

    Examples
    --------
    >>> from epistemica.sim import Scenario
    >>> from epistemica.del_ import parse_formula
    >>> s = Scenario("allocation", [[0, 0], [9, 9]], [[1, 1], [8, 8]], ["range"] * 2,
    ...              told=[((True, False), parse_formula("assigned(r1, g2)"))])
    >>> initial_knowledge(s).possible((0,), s.configurations()).tolist()
    [False, True]
    """
    k = TeamKnowledge(scenario.robot_names, scenario.goal_names, scenario.known_goals)
    for observers, formula in scenario.suggested:
        k.suggest(formula, observers)
    for observers, formula in scenario.told:
        k.tell(formula, observers)
    return k
