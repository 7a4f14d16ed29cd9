"""One observed event: what it teaches, and which agents observed it.

An :class:`Observation` is an action model of the mA* family (see
:mod:`epistemica.del_.explicit.observability`) whose observers are fixed when it happens:
*full* observers see what happened, *partial* observers see that it happened but not its
outcome, every other agent is *oblivious* and believes nothing happened. What it teaches:

- ``pre F`` (hard): every observer, full or partial, learns that ``F`` holds (the
  precondition of the event). Knowledge, never revised.
- ``senses F`` with its ``outcome`` (hard): full observers learn whether ``F`` holds;
  partial observers only that it was sensed. (An announcement of ``F`` in the spec
  language's sense, full observers learning ``F`` and partial ones only that ``F`` was
  announced or denied, is ``senses F`` with outcome ``True``.)
- ``suggests F`` (soft): full observers come to believe ``F``, a private *radical upgrade*:
  later evidence may override it (the newest upgrade that is consistent wins). A robot seen
  standing at a goal suggests that the goal is its; it may still leave.
- ``aware`` (atoms): full observers become aware of the atoms (they now conceive of worlds
  where those atoms are true: a goal discovered, a door that may be closed).
- ``withdraws`` (facts): an ontic change. The event may have made these facts false (a
  closed goal opens), so every observer, full or partial, drops what it learnt of them
  before as hard evidence; what it learns of them afterwards stands. Oblivious agents
  keep the old facts: they believe nothing changed.

Observers know who else observed (the observer sets are common knowledge among them).
:meth:`Observation.action_model` gives the hard part as an ordinary
:class:`~epistemica.del_.ActionModel`, the reference that
:class:`~epistemica.del_.state.EpistemicState` is tested against.

Examples
--------
>>> seen = Observation("settle", full={"r1", "r2"}, suggests="assigned(r3, g1)")
>>> sorted(seen.full), seen.partial, str(seen.suggests)
(['r1', 'r2'], frozenset(), 'assigned(r3, g1)')
>>> Observation("door", full={"r1"}, senses="closed", outcome=True).hard_fact(full=True)
Atom(name='closed', args=())
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.explicit.observability import observability_action
from epistemica.del_.language.formula import (
    And,
    Atom,
    Bottom,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    Top,
)
from epistemica.del_.language.parser import as_formula

__all__ = ["Observation"]


def _agents(value: Iterable[str] | str, what: str) -> frozenset[str]:
    if isinstance(value, str):
        value = [value]
    out = frozenset(str(a) for a in value)
    if not all(out):
        raise InvalidArgumentError(f"{what} names an empty agent", hint="agent names")
    return out


_PROPOSITIONAL = (Atom, Top, Bottom, Not, And, Or, Implies, Iff)


def _formula(value: Formula | str | None, what: str) -> Formula | None:
    if value is None:
        return None
    tree = as_formula(value)
    if not all(isinstance(f, _PROPOSITIONAL) for f in tree.subformulas()):
        raise InvalidArgumentError(
            f"{what} must be a fact about the world, got {value!s}",
            hint="observations teach propositional facts; K, B, ... are what they change",
        )
    return tree


@dataclass(frozen=True)
class Observation:
    """An event, what it teaches, and its observers (the others are oblivious).

    Parameters
    ----------
    name : str
        What happened (``"settle"``, ``"door_closes"``): for messages and bookkeeping.
    full, partial : iterable of str
        Agents that see what happened / only that it happened. An agent in both is full.
    pre, senses, suggests : formula or str, optional
        The hard fact every observer learns; the fact full observers learn the truth of
        (``outcome`` says which); the soft fact full observers come to believe.
    outcome : bool, optional
        Whether ``senses`` holds where the event happened (required with ``senses``).
    aware : iterable of str
        Atoms the full observers become aware of.
    withdraws : iterable of formula or str
        Facts the event may have changed: earlier hard evidence of exactly these facts no
        longer binds its observers (a goal seen closed that this event opens).
    args : tuple
        The event's arguments, kept for the caller (which robot settled where, ...).
    """

    name: str
    full: frozenset[str]
    partial: frozenset[str] = frozenset()
    pre: Formula | None = None
    senses: Formula | None = None
    outcome: bool | None = None
    suggests: Formula | None = None
    aware: frozenset[str] = frozenset()
    args: tuple = field(default=())
    withdraws: tuple[Formula, ...] = ()

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if not isinstance(self.name, str) or not self.name:
            raise InvalidArgumentError("an observation needs a name", hint="e.g. 'settle'")
        full = _agents(self.full, "full")
        set_(self, "full", full)
        set_(self, "partial", _agents(self.partial, "partial") - full)
        set_(self, "pre", _formula(self.pre, "pre"))
        set_(self, "senses", _formula(self.senses, "senses"))
        set_(self, "suggests", _formula(self.suggests, "suggests"))
        set_(self, "aware", frozenset(str(a) for a in self.aware))
        if (self.senses is None) != (self.outcome is None):
            raise InvalidArgumentError(
                f"observation {self.name!r}: 'senses' and 'outcome' go together",
                hint="give the sensed formula and whether it held",
            )
        if self.outcome is not None:
            set_(self, "outcome", bool(self.outcome))
        set_(self, "args", tuple(self.args))
        if isinstance(self.withdraws, (str, Formula)):
            raise InvalidArgumentError(
                f"observation {self.name!r}: 'withdraws' takes a sequence of facts",
                hint="e.g. withdraws=['closed_g1']",
            )
        set_(self, "withdraws", tuple(_formula(f, "withdraws") for f in self.withdraws))

    @property
    def observers(self) -> frozenset[str]:
        """Every agent that is not oblivious of the event."""
        return self.full | self.partial

    @property
    def content(self) -> tuple:
        """What the event is, without who observed it: two observations with the same
        content are the same event seen by possibly different agents."""
        return (self.name, self.args, self.pre, self.senses, self.outcome, self.suggests,
                self.aware, self.withdraws)  # fmt: skip

    def hard_fact(self, full: bool) -> Formula | None:
        """What an observer learns for certain: the precondition, and the sensed fact's
        outcome if it observed ``full``-y. ``None`` if nothing."""
        parts = [] if self.pre is None else [self.pre]
        if full and self.senses is not None:
            parts.append(self.senses if self.outcome else Not(self.senses))
        if not parts:
            return None
        out = parts[0]
        for part in parts[1:]:
            out = out & part
        return out

    def action_model(self, agents: Iterable[str]) -> ActionModel:
        """The hard part of the event as an action model over ``agents``: its precondition
        and sensed fact with their observers (the reference of the product update; a
        withdrawal, being an ontic change, is not part of it).

        Examples
        --------
        >>> from epistemica.del_ import KripkeModel
        >>> m = KripkeModel.from_observables(["p"], {"a": [], "b": []}, designated=["p"])
        >>> seen = Observation("look", full={"a"}, senses="p", outcome=True)
        >>> m.update(seen.action_model(["a", "b"])).holds("K[a] p & ~Kw[b] p & B[b] ~Kw[a] p")
        True
        """
        agent_list = list(agents)
        unknown = self.observers - set(agent_list)
        if unknown:
            raise InvalidArgumentError(
                f"observation {self.name!r} names unknown agents {sorted(unknown)}",
                hint=f"agents: {', '.join(agent_list)}",
            )
        executable = None
        if self.senses is not None:
            executable = self.senses if self.outcome else Not(self.senses)
        return observability_action(
            agent_list,
            pre=Top() if self.pre is None else self.pre,
            senses=self.senses,
            full=sorted(self.full),
            partial=sorted(self.partial),
            name=self.name,
            executable=executable,
        )
