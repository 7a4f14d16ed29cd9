"""The modal nodes of the formula language: what a formula says about agents and actions.

The individual modalities ``K[a] f`` (knowledge), ``B[a] f`` (belief) and ``Kw[a] f``
(knowing whether); the group modalities ``E`` (everybody knows), ``C`` (common knowledge),
``D`` (distributed knowledge), ``EB`` (everybody believes) and ``CB`` (common belief);
public announcements ``[!f] g`` and ``<!f> g``, and named actions ``[ACT] g``; for
plausibility models, conditional belief ``B[a | f] g``, safe belief ``Sb[a] f`` and the
public soft upgrades ``[^^f] g`` (radical) and ``[^f] g`` (conservative).

The base class, atoms and the Boolean connectives are in
:mod:`~epistemica.del_.language.formula`; import both from :mod:`epistemica.del_`. Every
modal node is a unary prefix operator: it binds its operand at its own (the unary)
precedence.

Examples
--------
>>> from epistemica.del_.language.formula import Atom
>>> f = Common(["b", "a", "b"], RadicalUpgrade(Atom("p"), Believe("a", Atom("p"))))
>>> print(f)
C[a, b] [^^p] B[a] p
>>> sorted(f.agents()), f.modal_depth()
(['a', 'b'], 2)
"""

from __future__ import annotations

from dataclasses import dataclass

from epistemica.del_.language.formula import Formula, TextPart

__all__ = [
    "After",
    "Announce",
    "AnnounceDiamond",
    "Believe",
    "Common",
    "CommonBelief",
    "ConditionalBelief",
    "ConservativeUpgrade",
    "Distributed",
    "Everybody",
    "EverybodyBelieves",
    "Know",
    "KnowWhether",
    "RadicalUpgrade",
    "SafeBelief",
]


class _Individual(Formula):
    """A modality of one agent: ``OP[agent] operand``."""

    __slots__ = ()
    keyword = ""
    epistemic = True

    def own_agents(self) -> tuple[str, ...]:
        return (self.agent,)  # type: ignore[attr-defined]

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)  # type: ignore[attr-defined]

    def text_parts(self) -> tuple[TextPart, ...]:
        agent, operand = self.agent, self.operand  # type: ignore[attr-defined]
        return (f"{self.keyword}[{agent}] ", (operand, self.precedence))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Know(_Individual):
    """``K[a] f``: agent ``a`` knows ``f`` (box over a's knowledge relation)."""

    agent: str
    operand: Formula
    keyword = "K"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Believe(_Individual):
    """``B[a] f``: agent ``a`` believes ``f`` (box over a's belief relation)."""

    agent: str
    operand: Formula
    keyword = "B"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class KnowWhether(_Individual):
    """``Kw[a] f``: agent ``a`` knows whether ``f``, i.e. ``K[a] f | K[a] ~f``."""

    agent: str
    operand: Formula
    keyword = "Kw"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class ConditionalBelief(_Individual):
    """``B[a | c] f``: ``f`` holds at the most plausible worlds of a's cell where ``c`` holds.

    Interpreted in plausibility models only (:mod:`~epistemica.del_.explicit.plausibility`);
    ``B[a | true] f`` is ``B[a] f`` there. ``|`` separates the agent from the condition so
    that ``B[a] (f | g)`` keeps meaning belief in a disjunction.
    """

    agent: str
    condition: Formula
    operand: Formula
    keyword = "B"

    def children(self) -> tuple[Formula, ...]:
        return (self.condition, self.operand)

    def text_parts(self) -> tuple[TextPart, ...]:
        return (f"B[{self.agent} | ", (self.condition, 0), "] ", (self.operand, self.precedence))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class SafeBelief(_Individual):
    """``Sb[a] f``: ``f`` holds at every world of a's cell at least as plausible as this one.

    Baltag and Smets' safe belief (the box of the plausibility preorder): it survives every
    truthful revision. Interpreted in plausibility models only.
    """

    agent: str
    operand: Formula
    keyword = "Sb"


class _Group(Formula):
    """A modality of a group of agents: ``OP[a, b] operand``."""

    __slots__ = ()
    keyword = ""
    epistemic = True

    def __post_init__(self) -> None:
        group = tuple(sorted(set(self.group)))  # type: ignore[attr-defined]
        if not group:
            raise ValueError(f"{self.keyword}[...] needs at least one agent")
        object.__setattr__(self, "group", group)
        Formula.__post_init__(self)

    def own_agents(self) -> tuple[str, ...]:
        return self.group  # type: ignore[attr-defined]

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)  # type: ignore[attr-defined]

    def text_parts(self) -> tuple[TextPart, ...]:
        group, operand = ", ".join(self.group), self.operand  # type: ignore[attr-defined]
        return (f"{self.keyword}[{group}] ", (operand, self.precedence))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Everybody(_Group):
    """``E[a, b] f``: every agent of the group knows ``f``."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "E"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Common(_Group):
    """``C[a, b] f``: ``f`` is common knowledge in the group."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "C"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Distributed(_Group):
    """``D[a, b] f``: ``f`` is distributed knowledge in the group."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "D"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class EverybodyBelieves(_Group):
    """``EB[a, b] f``: every agent of the group believes ``f``."""

    group: tuple[str, ...]
    operand: Formula
    keyword = "EB"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class CommonBelief(_Group):
    """``CB[a, b] f``: ``f`` is common belief in the group.

    ``f`` holds at every world reachable in one or more steps by the union of the group's
    *belief* relations (``C`` uses the knowledge relations).
    """

    group: tuple[str, ...]
    operand: Formula
    keyword = "CB"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class Announce(Formula):
    """``[!f] g``: after every truthful public announcement of ``f``, ``g`` holds."""

    announcement: Formula
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.announcement, self.operand)

    def text_parts(self) -> tuple[TextPart, ...]:
        return ("[!", (self.announcement, 0), "] ", (self.operand, self.precedence))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class AnnounceDiamond(Formula):
    """``<!f> g``: ``f`` is true (so announceable) and after announcing it ``g`` holds."""

    announcement: Formula
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.announcement, self.operand)

    def text_parts(self) -> tuple[TextPart, ...]:
        return ("<!", (self.announcement, 0), "> ", (self.operand, self.precedence))


class _Upgrade(Formula):
    """A public soft announcement ``[OPEN f] g``: the operand holds after the upgrade."""

    __slots__ = ()
    opener = ""

    def children(self) -> tuple[Formula, ...]:
        return (self.upgrade, self.operand)  # type: ignore[attr-defined]

    def text_parts(self) -> tuple[TextPart, ...]:
        upgrade, operand = self.upgrade, self.operand  # type: ignore[attr-defined]
        return (f"[{self.opener}", (upgrade, 0), "] ", (operand, self.precedence))


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class RadicalUpgrade(_Upgrade):
    """``[^^f] g`` (also ``[⇑f] g``): after the radical upgrade with ``f``, ``g`` holds.

    In every information cell the ``f``-worlds become more plausible than all the others,
    the order within each of the two zones kept (van Benthem's ⇑, Baltag and Smets'
    lexicographic upgrade). Always executable.
    """

    upgrade: Formula
    operand: Formula
    opener = "^^"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class ConservativeUpgrade(_Upgrade):
    """``[^f] g`` (also ``[↑f] g``): after the conservative upgrade with ``f``, ``g`` holds.

    In every information cell only the most plausible ``f``-worlds move to the top; the
    rest of the order is kept (van Benthem's ↑). Always executable.
    """

    upgrade: Formula
    operand: Formula
    opener = "^"


@dataclass(frozen=True, slots=True, eq=False, repr=False)
class After(Formula):
    """``[ACT] g``: after every execution of the named action ``ACT``, ``g`` holds.

    The name is resolved against the actions passed to the model checker.
    """

    action: str
    operand: Formula

    def children(self) -> tuple[Formula, ...]:
        return (self.operand,)

    def text_parts(self) -> tuple[TextPart, ...]:
        return (f"[{self.action}] ", (self.operand, self.precedence))
