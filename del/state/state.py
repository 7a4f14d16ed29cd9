"""The epistemic state of a group of agents, updated by the events each of them observed.

:class:`EpistemicState` records :class:`~epistemica.del_.state.Observation` s with their
observers, and answers for any *group* of agents (a chain ``i1, i2, ..., ik``: what ``i1``
thinks ``i2`` thinks ... ``ik`` considers possible) which observations the whole group
observed. It holds no worlds: the worlds are evaluated by a backend,
:mod:`~epistemica.del_.state.explicit` (a table of worlds, boolean masks) or
:mod:`~epistemica.del_.state.symbolic` (a law on BDDs).

The group semantics
-------------------
A chain reaches, from the actual world, the worlds that its *group* ``S = {i1, ..., ik}``
cannot rule out with what every member observed (observers know who else observed, so each
member knows what the others of ``S`` saw of it). With ``H(S)`` the observations every
member of ``S`` observed (fully or partially) and ``F(S)`` those every member observed
fully:

- ``K(S)``: the worlds where every fact announced in ``H(S)`` holds, and every fact sensed
  in ``F(S)`` has its outcome. Hard evidence only; never empty at the actual world.
  A fact an observation in ``H(S)`` *withdraws* (an ontic change: a closed goal opens)
  no longer counts when it was learnt before that observation.
- ``B(S)``: of those, the *conceivable* ones (every tracked atom true there is one the
  group is aware of, through an ``aware`` observation in ``F(S)``), then the soft facts of
  ``F(S)`` applied newest first, each kept only if some world is left (a lexicographic
  radical upgrade: the newest consistent evidence wins). The ``"primacy"`` revision
  (an ablation, :func:`soft_in_order`) applies them oldest first instead.
  ``B(S)`` is empty when the group learnt a hard fact that only worlds it cannot
  conceive of satisfy (a partial observer told of a fact about an atom it is not aware
  of): its belief is inconsistent, and every ``B`` formula holds at its copies.

``K[i1] K[i2] ... K[ik] f`` (``f`` propositional) holds iff ``f`` holds on ``K(S)``, and
``B[i1] ... B[ik] f`` iff ``f`` holds on ``B(S)`` provided no shorter chain's group
``{i1, ..., ij}`` has an empty ``B`` (else it holds vacuously). The group models
(:func:`~.explicit.group_model`, :func:`~.symbolic.group_structure`) answer every formula;
for hard evidence they give the verdicts of the product update of the observations'
action models (tests/del/test_state.py checks it on random histories and formulas of
every modality), and they extend it with awareness and soft evidence.

An observation that teaches no group anything it had not observed already (the same
content, observers within an earlier one's, and for a soft fact no other soft fact
observed by any of them since) is not recorded.

Examples
--------
Robot ``a`` sees ``c`` settle at ``g1``; ``b`` does not:

>>> s = EpistemicState(["a", "b", "c"])
>>> s.observe(Observation("settle", full={"a", "c"}, suggests="at_c_g1"))
True
>>> [str(f) for f in s.soft(("a",))], s.soft(("a", "b"))
(['at_c_g1'], ())
>>> s.observe(Observation("settle", full={"a"}, suggests="at_c_g1"))  # nothing new
False
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import NamedTuple

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import Formula
from epistemica.del_.state.observation import Observation

__all__ = ["REVISIONS", "EpistemicState", "History", "soft_in_order"]

#: How soft facts revise a belief: the newest consistent one wins, or the oldest.
REVISIONS = ("recency", "primacy")

Chain = Sequence[str] | Sequence[int]


class History(NamedTuple):
    """What a group observed: its hard facts (oldest first), soft facts (newest first)
    and the atoms it is aware of."""

    hard: tuple[Formula, ...]
    soft: tuple[Formula, ...]
    aware: frozenset[str]


class EpistemicState:
    """Observations of a group of agents, answered per group.

    Parameters
    ----------
    agents : sequence of str
        The agents, in order (a chain may name them or give their indices).
    tracked : iterable of str
        Atoms subject to awareness: an agent conceives of a world where such an atom is
        true only after an observation made it aware of the atom. Other atoms are
        conceived by everyone.
    """

    def __init__(self, agents: Sequence[str], tracked: Iterable[str] = ()) -> None:
        self._agents = tuple(str(a) for a in agents)
        if not self._agents or len(set(self._agents)) != len(self._agents):
            raise InvalidArgumentError(
                f"agents must be distinct names, got {list(agents)!r}", hint="e.g. ['r1', 'r2']"
            )
        self._index = {a: i for i, a in enumerate(self._agents)}
        self._tracked = frozenset(str(a) for a in tracked)
        self._observations: list[Observation] = []
        self._observed: list[int] = []  # bitmask of the full and partial observers
        self._full: list[int] = []  # bitmask of the full observers
        self._by_content: dict[tuple, list[int]] = {}
        self._groups: dict[int, _Group] = {}  # per group bitmask, until the next observation
        self._soft: list[int] = []  # indices of the observations with a soft fact
        self._withdrawing: list[int] = []  # indices of the observations that withdraw facts

    # -- the record --------------------------------------------------------------------

    @property
    def agents(self) -> tuple[str, ...]:
        """The agents, in order."""
        return self._agents

    @property
    def tracked(self) -> frozenset[str]:
        """The atoms subject to awareness."""
        return self._tracked

    @property
    def observations(self) -> tuple[Observation, ...]:
        """Every recorded observation, oldest first."""
        return tuple(self._observations)

    def __len__(self) -> int:
        return len(self._observations)

    def __repr__(self) -> str:
        return f"EpistemicState({len(self._agents)} agents, {len(self)} observations)"

    def bits(self, agents: Iterable[str] | Iterable[int]) -> int:
        """The bitmask of a group given by names or indices."""
        out = 0
        for a in agents:
            if isinstance(a, str):
                if a not in self._index:
                    raise InvalidArgumentError(
                        f"unknown agent {a!r}", hint=f"agents: {', '.join(self._agents)}"
                    )
                out |= 1 << self._index[a]
            elif isinstance(a, bool) or not 0 <= int(a) < len(self._agents):
                raise InvalidArgumentError(
                    f"agent index {a!r} out of range", hint=f"0..{len(self._agents) - 1}"
                )
            else:
                out |= 1 << int(a)
        return out

    def observe(self, observation: Observation) -> bool:
        """Record an observation; ``False`` (and nothing recorded) if every group that
        observed it had observed the same already. An event nobody observed is recorded
        too: it happened, so the actual world satisfies its precondition."""
        if not isinstance(observation, Observation):
            raise InvalidArgumentError(
                f"expected an Observation, got {type(observation).__name__}",
                hint="build one with epistemica.del_.Observation(...)",
            )
        full, seen = self.bits(observation.full), self.bits(observation.observers)
        earlier = self._by_content.setdefault(observation.content, [])
        for i in earlier:
            if (
                self._full[i] & full == full
                and self._observed[i] & seen == seen
                and not self._soft_since(i, observation, full)
                and not self._withdrawn_since(i, observation)
            ):
                return False
        earlier.append(len(self._observations))
        if observation.suggests is not None:
            self._soft.append(len(self._observations))
        if observation.withdraws:
            self._withdrawing.append(len(self._observations))
        self._groups.clear()
        self._observations.append(observation)
        self._observed.append(seen)
        self._full.append(full)
        return True

    def _soft_since(self, i: int, observation: Observation, full: int) -> bool:
        """Whether a soft fact reached one of ``full`` after observation ``i``: then a
        repeat of ``i``'s soft fact is the newest evidence again, not a repeat."""
        if observation.suggests is None:
            return False
        for j in reversed(self._soft):
            if j <= i:
                return False
            if self._full[j] & full:
                return True
        return False

    def _withdrawn_since(self, i: int, observation: Observation) -> bool:
        """Whether an observation after ``i`` withdrew one of ``observation``'s hard
        facts: then the same evidence again is news (the goal closed again)."""
        facts = {observation.hard_fact(True), observation.hard_fact(False)} - {None}
        return any(
            j > i and facts.intersection(self._observations[j].withdraws) for j in self._withdrawing
        )

    # -- groups ------------------------------------------------------------------------

    def _group(self, chain: Chain) -> _Group:
        """What the chain's group observed, computed once per group until the next
        observation."""
        c = self.bits(chain)
        found = self._groups.get(c)
        if found is None:
            seen = tuple(i for i, b in enumerate(self._observed) if b & c == c)
            full = tuple(i for i in seen if self._full[i] & c == c)
            found = self._groups[c] = _Group(seen, full, self._history(seen, full))
        return found

    def _history(self, seen: tuple[int, ...], full: tuple[int, ...]) -> History:
        fully = set(full)
        hard: list[Formula] = []
        for i in seen:
            observation = self._observations[i]
            if observation.withdraws:  # an ontic change: earlier evidence of these is void
                hard = [fact for fact in hard if fact not in observation.withdraws]
            fact = observation.hard_fact(i in fully)
            if fact is not None:
                hard.append(fact)
        soft = tuple(
            self._observations[i].suggests
            for i in reversed(full)
            if self._observations[i].suggests is not None
        )
        aware: set[str] = set()
        for i in full:
            aware |= self._observations[i].aware
        return History(tuple(hard), soft, frozenset(aware & self._tracked))

    def observed(self, chain: Chain, fully: bool = False) -> tuple[int, ...]:
        """Indices of the observations every agent of ``chain`` observed (``fully``: as a
        full observer), oldest first. The empty chain is the actual world: every one."""
        group = self._group(chain)
        return group.full if fully else group.seen

    def history(self, chain: Chain) -> History:
        """What ``chain``'s group observed: hard facts, soft facts, awareness."""
        return self._group(chain).history

    def hard(self, chain: Chain) -> tuple[Formula, ...]:
        """The hard facts ``chain``'s group learnt, oldest first."""
        return self._group(chain).history.hard

    def soft(self, chain: Chain) -> tuple[Formula, ...]:
        """The soft facts ``chain``'s group was shown, newest first."""
        return self._group(chain).history.soft

    def aware(self, chain: Chain) -> frozenset[str]:
        """The tracked atoms ``chain``'s group is aware of."""
        return self._group(chain).history.aware

    def signature(self, chain: Chain) -> tuple:
        """What the chain's group observed, as a hashable key: groups with equal
        signatures have equal ``K`` and ``B`` sets on any worlds."""
        group = self._group(chain)
        return group.seen, group.full, group.history.aware

    def constrains(self, chain: Chain) -> bool:
        """Whether any hard or soft fact reaches the chain's group (awareness aside)."""
        history = self._group(chain).history
        return bool(history.hard or history.soft)


class _Group(NamedTuple):
    seen: tuple[int, ...]
    full: tuple[int, ...]
    history: History


def soft_in_order(state: EpistemicState, chain: Chain, revision: str = "recency") -> tuple:
    """The soft facts of ``chain``'s group in the order they revise its belief: newest
    first under ``"recency"`` (the newest consistent fact wins), oldest first under
    ``"primacy"`` (the first consistent fact the group was shown is kept: the ablation).

    Examples
    --------
    >>> s = EpistemicState(["a"])
    >>> for goal in ("g1", "g2"):
    ...     _ = s.observe(Observation("settle", full={"a"}, suggests=f"at_{goal}"))
    >>> [str(f) for f in soft_in_order(s, ("a",))]
    ['at_g2', 'at_g1']
    >>> [str(f) for f in soft_in_order(s, ("a",), "primacy")]
    ['at_g1', 'at_g2']
    """
    if revision not in REVISIONS:
        raise InvalidArgumentError(
            f"unknown revision {revision!r}", hint="use 'recency' (default) or 'primacy'"
        )
    soft = state.soft(chain)
    return soft if revision == "recency" else soft[::-1]
