"""Action models from observability: who sees an action fully, partially or not at all.

:func:`observability_action` builds the event model of one action in the style of the
action language mA* (Baral et al.): the action may change atoms (``effects``), let its
observers sense the truth of a formula (``senses``) or announce a formula
(``announces``); each agent is *fully observant* (sees which event happened),
*partially observant* (sees that the action happened, not its outcome) or *oblivious*
(believes nothing happened). Which of the three an agent is may depend on the state,
through a condition formula evaluated at the world where the action happens ("agents
looking at the box see it opened"). Everything compiles to ONE event model whose edges
carry those conditions.

Events: one *real* event per outcome (sensing ``f``: ``pre & f`` and ``pre & ~f``;
announcing ``F``: ``pre & F``, plus ``pre & ~F`` for partial observers; otherwise just
``pre``), all with the same effects, and a ``(skip)`` event (precondition ``true``, no
effect) for oblivious agents. For agent ``i`` with full condition ``F_i`` and partial
condition ``P_i``:

========================  ===============================  ==========================
edge                      belief relation (``B``)           knowledge relation (``K``)
========================  ===============================  ==========================
real e -> same outcome    ``F_i | P_i``                     ``true``
real e -> other outcome   ``P_i & ~F_i``                    ``~F_i``
real e <-> ``(skip)``     e -> skip if ``~F_i & ~P_i``      both ways if ``~F_i & ~P_i``
``(skip)`` -> ``(skip)``  ``true``                          ``true``
========================  ===============================  ==========================

So beliefs of oblivious agents point at ``(skip)`` (they may become false), while the
knowledge relation stays an equivalence on events within each of the three regions
(full: one class per outcome; partial: all real events; oblivious: all events). The
product of an S5 knowledge relation with it is again an equivalence **provided each
agent knows its own observability conditions**, i.e. ``F_i`` and ``P_i`` have the same
truth value at worlds the agent cannot tell apart: then ``(w, e) ~ (v, f)`` needs
``w ~ v`` and an event pair of the region both ``w`` and ``v`` lie in. Knowledge thus
stays veridical, and the belief relation is contained in it.

``executable`` gives an *executability condition* in the sense of mA*: it must hold at
the actual (designated) world for the action to happen, but it is not part of the events
the agents observe. It is compiled into a designated copy of each real event (with
``pre & executable``) whose edges lead to non-designated "as observed" copies (with
``pre`` only). Use it when an agent may observe an action whose precondition contradicts
its (false) beliefs: with the precondition inside the events, that agent's beliefs would
become empty and it would believe everything.

Examples
--------
``a`` peeks at a coin, ``b`` sees ``a`` peek, ``c`` is oblivious:

>>> from epistemica.del_ import KripkeModel
>>> m = KripkeModel.from_observables(["heads"], {"a": [], "b": [], "c": []},
...                                  designated=["heads"])
>>> peek = observability_action(["a", "b", "c"], senses="heads", full=["a"],
...                             partial=["b"], name="peek")
>>> peek.events
('peek[heads]', 'peek[~heads]', '(skip)')
>>> after = m.update(peek)
>>> after.holds("K[a] heads & K[b] Kw[a] heads & ~Kw[b] heads & B[c] ~Kw[a] heads")
True
>>> after.holds("K[c] ~Kw[a] heads")   # c believes a ignorant, but does not know it
False
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.language.formula import And, Bottom, Formula, Not, Or, Top, canonical_atom
from epistemica.del_.language.parser import as_formula

__all__ = ["SKIP_EVENT", "observability_action"]

SKIP_EVENT = "(skip)"

Condition = Formula | str | bool


def observability_action(
    agents: Iterable[str],
    pre: Formula | str = "true",
    effects: Mapping[str, Condition] | None = None,
    senses: Formula | str | Iterable[Formula | str] | None = None,
    announces: Formula | str | None = None,
    full: Mapping[str, Condition] | Iterable[str] | str = (),
    partial: Mapping[str, Condition] | Iterable[str] | str = (),
    name: str = "action",
    *,
    executable: Formula | str | None = None,
) -> ActionModel:
    """Compile an mA*-style action into one event model with conditioned edges.

    Parameters
    ----------
    agents : iterable of str
        Every agent of the models the action will update.
    pre : formula or str
        Precondition, part of every real event (agents observing the action learn it).
    effects : mapping, optional
        Atom -> formula (or bool): the atom's new value, evaluated before the action.
    senses : formula, str or iterable of them, optional
        Formulas whose truth the full observers learn (one event per combination of
        truth values). Exclusive with ``announces``.
    announces : formula or str, optional
        A formula full observers learn to be true; partial observers learn only that
        it was announced or denied.
    full, partial : mapping or iterable of str
        Agent -> condition (formula, text or bool) under which it observes fully /
        partially; a plain iterable (or one name) means "always". An agent in neither
        is oblivious; an agent in both is full where its full condition holds.
    name : str
        Stem of the event names.
    executable : formula or str, optional
        mA* executability condition, checked at the designated worlds only (see the
        module notes).

    Returns
    -------
    ActionModel

    Raises
    ------
    InvalidArgumentError
        Unknown or repeated agents, both ``senses`` and ``announces``, a malformed
        condition or effect.

    Examples
    --------
    A public assignment has one event and no ``(skip)``:

    >>> observability_action(["a", "b"], effects={"p": True}, full=["a", "b"]).events
    ('action',)
    """
    agent_list = _agents(agents)
    full_of = _conditions(full, agent_list, "full")
    partial_of = _conditions(partial, agent_list, "partial")
    if senses is not None and announces is not None:
        raise InvalidArgumentError(
            "an action cannot both sense and announce",
            hint="split it into two actions, or announce the sensed formula",
        )
    if not isinstance(name, str) or not name:
        raise InvalidArgumentError("name must be a non-empty string", hint="e.g. name='peek'")
    pre_f = _formula(pre, "pre")
    changes = _effects(effects)
    regions = _regions(agent_list, full_of, partial_of)
    any_partial = any(not isinstance(r[2], Bottom) for r in regions.values())
    outcomes = _outcomes(senses, announces, name, any_partial)
    exec_f = None if executable is None else _formula(executable, "executable")
    if isinstance(exec_f, Top):
        exec_f = None
    return _event_model(regions, outcomes, pre_f, exec_f, changes)


def _event_model(
    regions: dict[str, tuple[Formula, ...]],
    outcomes,
    pre_f: Formula,
    exec_f: Formula | None,
    changes: dict,
) -> ActionModel:
    """The event model: the real events of the outcomes, ``(skip)`` when some agent may
    be oblivious, and each agent's edges by its observation regions."""
    any_oblivious = any(not isinstance(r[3], Bottom) for r in regions.values())
    events, pres, seen, sources, designated = _events(outcomes, pre_f, exec_f)
    posts = {e: dict(changes) for e in events}
    if any_oblivious:
        events.append(SKIP_EVENT)
    relations: dict[str, list[tuple]] = {}
    knowledge: dict[str, list[tuple]] = {}
    for a, region in regions.items():
        relations[a], knowledge[a] = _agent_edges(region, seen, sources, any_oblivious)
    return ActionModel(events, pres, posts, relations, designated, knowledge)


def _regions(agent_list, full_of, partial_of) -> dict[str, tuple[Formula, ...]]:
    """Per agent: where it observes fully, fully or partially, partially only, not at all."""
    regions = {}
    for a in agent_list:
        f, p = full_of.get(a, Bottom()), partial_of.get(a, Bottom())
        regions[a] = (f, _or(f, p), _and(p, _not(f)), _and(_not(f), _not(p)))
    return regions


def _events(outcomes, pre_f: Formula, exec_f: Formula | None):
    """The real events: one per outcome, plus an executable copy of each designated one
    when there is an executability condition. Returns the events, their preconditions,
    ``seen`` (each outcome's event as the agents see it), ``sources`` (every real event
    with its outcome) and the designated events."""
    events: list[str] = []
    pres: dict[str, Formula] = {}
    seen: list[tuple[str, int]] = []
    sources: list[tuple[str, int]] = []
    designated: list[str] = []
    for k, (event, content, is_designated) in enumerate(outcomes):
        base = _and(pre_f, content)
        events.append(event)
        pres[event] = base
        seen.append((event, k))
        sources.append((event, k))
        if exec_f is None:
            if is_designated:
                designated.append(event)
        elif is_designated:
            real = event + "!"
            events.append(real)
            pres[real] = _and(base, exec_f)
            sources.append((real, k))
            designated.append(real)
    return events, pres, seen, sources, designated


def _agent_edges(region, seen, sources, any_oblivious: bool) -> tuple[list, list]:
    """One agent's conditioned belief and knowledge edges."""
    f, same, other, oblivious = region
    belief: list[tuple] = []
    know: list[tuple] = []
    for source, k in sources:
        for target, kk in seen:
            _edge(belief, source, target, same if k == kk else other)
        for target, kk in sources:
            _edge(know, source, target, Top() if k == kk else _not(f))
        if any_oblivious:
            _edge(belief, source, SKIP_EVENT, oblivious)
            _edge(know, source, SKIP_EVENT, oblivious)
            _edge(know, SKIP_EVENT, source, oblivious)
    if any_oblivious:
        belief.append((SKIP_EVENT, SKIP_EVENT))
        know.append((SKIP_EVENT, SKIP_EVENT))
    return belief, know


def _edge(edges: list[tuple], e: str, f: str, condition: Formula) -> None:
    if isinstance(condition, Bottom):
        return
    edges.append((e, f) if isinstance(condition, Top) else (e, f, condition))


def _outcomes(
    senses: object, announces: object, name: str, any_partial: bool
) -> list[tuple[str, Formula, bool]]:
    """(event name, content, designated) per real event."""
    if announces is not None:
        told = _formula(announces, "announces")
        found = [(name, told, True)]
        if any_partial:
            found.append((f"{name}[~]", _not(told), False))
        return found
    if senses is None:
        return [(name, Top(), True)]
    sensed = (
        [_formula(senses, "senses")]
        if isinstance(senses, (Formula, str))
        else [_formula(s, "senses") for s in senses]
    )
    if not sensed:
        raise InvalidArgumentError("senses is empty", hint="give at least one formula")
    found = []
    for signs in itertools.product((True, False), repeat=len(sensed)):
        literals = [f if s else Not(f) for f, s in zip(sensed, signs, strict=True)]
        label = ", ".join(str(x) for x in literals)
        content = literals[0]
        for x in literals[1:]:
            content = And(content, x)
        found.append((f"{name}[{label}]", content, True))
    return found


def _agents(agents: Iterable[str]) -> list[str]:
    if isinstance(agents, str):
        agents = [agents]
    found = []
    for a in agents:
        if not isinstance(a, str) or not a:
            raise InvalidArgumentError(
                f"agent names must be non-empty strings, got {a!r}", hint="e.g. ['a', 'b']"
            )
        found.append(a)
    if not found:
        raise InvalidArgumentError("no agents given", hint="list every agent of the model")
    if len(set(found)) != len(found):
        raise InvalidArgumentError("agent names must be distinct", hint="remove the repeat")
    return found


def _conditions(spec: object, agents: list[str], what: str) -> dict[str, Formula]:
    if isinstance(spec, str):
        spec = [spec]
    if isinstance(spec, Mapping):
        pairs = [(a, _formula(c, f"{what}[{a!r}]")) for a, c in spec.items()]
    else:
        try:
            pairs = [(a, Top()) for a in spec]  # type: ignore[union-attr]
        except TypeError:
            raise InvalidArgumentError(
                f"{what} must map agents to conditions or list agents, got {spec!r}",
                hint=f"e.g. {what}=['a'] or {what}={{'a': 'looking(a)'}}",
            ) from None
    found: dict[str, Formula] = {}
    for a, c in pairs:
        if a not in agents:
            raise InvalidArgumentError(
                f"unknown agent {a!r} in {what}", hint=f"agents: {', '.join(agents)}"
            )
        found[a] = c
    return found


def _effects(effects: Mapping[str, Condition] | None) -> dict[str, Formula]:
    if effects is None:
        return {}
    if not isinstance(effects, Mapping):
        raise InvalidArgumentError(
            "effects must map atoms to formulas", hint="e.g. effects={'opened': True}"
        )
    found = {}
    for atom, value in effects.items():
        if not isinstance(atom, str) or not atom.strip():
            raise InvalidArgumentError(
                f"effect keys must be atom names, got {atom!r}", hint="e.g. 'at(r1, g1)'"
            )
        found[canonical_atom(atom)] = _formula(value, f"effects[{atom!r}]")
    return found


def _formula(value: object, what: str) -> Formula:
    if value is True:
        return Top()
    if value is False:
        return Bottom()
    if isinstance(value, (Formula, str)):
        return as_formula(value)
    raise InvalidArgumentError(
        f"{what} must be a formula, its text or a bool, got {type(value).__name__}",
        hint="e.g. 'looking(a)' or True",
    )


# Boolean folding keeps trivial conditions off the edges (the engine skips `true` edges).
def _and(x: Formula, y: Formula) -> Formula:
    if isinstance(x, Bottom) or isinstance(y, Bottom):
        return Bottom()
    if isinstance(x, Top):
        return y
    if isinstance(y, Top):
        return x
    return And(x, y)


def _or(x: Formula, y: Formula) -> Formula:
    if isinstance(x, Top) or isinstance(y, Top):
        return Top()
    if isinstance(x, Bottom):
        return y
    if isinstance(y, Bottom):
        return x
    return Or(x, y)


def _not(x: Formula) -> Formula:
    if isinstance(x, Top):
        return Bottom()
    if isinstance(x, Bottom):
        return Top()
    if isinstance(x, Not):
        return x.operand
    return Not(x)
