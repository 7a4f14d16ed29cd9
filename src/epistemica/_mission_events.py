"""Compiling the ``event`` declarations of mission files into event rules.

Helper of :mod:`epistemica._mission_compiler`. An event is an action model written in the
spec language's syntax (``announces``, ``senses``, ``suggests``, ``full``/``partial``
observers with ``if`` conditions) plus a ``when`` trigger and world effects; it compiles
into a :class:`~epistemica.sim.engine.events.EventRule`. Every name is checked: a robot, a goal, a
parameter of the event, or (in observer conditions) a quantity the simulator has. The
library events (``settle``, ``complete``) are written in the same syntax in ``events.epi``
next to this module (compiled by :func:`epistemica.mission.library_rules`).
"""

from __future__ import annotations

from typing import Any

from lark import Token, Tree

from epistemica.del_ import Formula
from epistemica.sim.engine.events import EventRule, ObserverRule, Trigger

__all__ = ["compile_event"]

DOMAINS = {"robots": "robots", "goals": "goals", "tasks": "goals"}
#: Observer predicates and their arities.
PREDICATES = {"sees": 1, "near": 2, "sensor": 1}
_CONTENT = ("pre", "announces", "senses", "suggests")


class _Event:
    """The names an event may use, and its pieces as they are compiled."""

    def __init__(self, comp: Any, name: Token, parameters: Tree | None) -> None:
        self.comp, self.name = comp, name
        self.parameters: dict[str, str] = {}
        for parameter in [] if parameters is None else parameters.children:
            pname, domain = parameter.children
            if str(domain) not in DOMAINS:
                raise comp.unknown("parameter domain", domain, DOMAINS)
            if str(pname) in self.parameters or comp.is_declared(str(pname)):
                raise comp.error(
                    f"parameter '{pname}' is declared twice or shadows a name",
                    pname,
                    "give the parameter a name of its own",
                )
            self.parameters[str(pname)] = DOMAINS[str(domain)]
        self.parts: dict[str, Any] = {"closes": [], "opens": [], "reveals": [], "full": [],
                                      "partial": []}  # fmt: skip

    def name_of(self, token: Token, kind: str) -> str:
        """A robot or goal (``kind``: "robot", "goal" or "place": either) or a parameter."""
        text = str(token)
        domain = self.parameters.get(text)
        if domain is not None:
            if kind != "place" and domain != kind + "s":
                raise self.comp.error(
                    f"parameter '{text}' ranges over {domain}, not {kind}s", token, "use "
                    f"a {kind} here"
                )  # fmt: skip
            return text
        if kind in ("robot", "place") and self.comp.is_robot(text):
            return text
        if kind in ("goal", "place") and self.comp.is_goal(text):
            return text
        known = [p for p, d in self.parameters.items() if kind == "place" or d == kind + "s"]
        known += self.comp.declared(kind)
        raise self.comp.unknown(kind if kind != "place" else "robot or goal", token, known)


def compile_event(comp: Any, node: Tree) -> EventRule:
    """The rule of one ``event NAME(...) { ... }`` declaration."""
    name, parameters, *items = node.children
    event = _Event(comp, name, parameters)
    trigger = None
    for item in items:
        kind = str(item.data)
        if kind == "when":
            if trigger is not None:
                raise comp.error("an event has one 'when'", item, "keep one trigger")
            trigger = _trigger(event, item.children[0])
        elif kind in ("closes", "opens", "reveals"):
            event.parts[kind].append(event.name_of(item.children[0], "goal"))
        elif kind in _CONTENT:
            if kind in event.parts:
                raise comp.error(f"'{kind}' is given twice", item, "join the facts with &")
            event.parts[kind] = _fact(event, item.children[0], sensed=kind == "senses")
        else:
            event.parts[kind].extend(_observer(event, o) for o in item.children[0].children)
    if trigger is None:
        raise comp.error(
            f"event '{name}' has no 'when'", name, "say when it happens, e.g. 'when step 20'"
        )
    _check_teaches(event, node)
    return EventRule(
        str(name),
        tuple(event.parameters.items()),
        trigger,
        closes=tuple(event.parts["closes"]),
        opens=tuple(event.parts["opens"]),
        pre=event.parts.get("pre"),
        announces=event.parts.get("announces"),
        senses=event.parts.get("senses"),
        suggests=event.parts.get("suggests"),
        reveals=tuple(event.parts["reveals"]),
        full=tuple(event.parts["full"]),
        partial=tuple(event.parts["partial"]),
    )


def _check_teaches(event: _Event, node: Tree) -> None:
    parts, comp = event.parts, event.comp
    if "announces" in parts and "senses" in parts:
        raise comp.error(
            f"event '{event.name}' both announces and senses",
            event.name,
            "split it into two events, or announce the sensed fact",
        )
    if not (parts["full"] or parts["partial"]):
        raise comp.error(
            f"event '{event.name}' has no observer",
            event.name,
            "add e.g. 'full robots if sees(r)': who sees it happen",
        )
    if not any(parts.get(k) for k in (*_CONTENT, "reveals", "closes", "opens")):
        raise comp.error(
            f"event '{event.name}' neither teaches nor changes anything",
            event.name,
            "give it 'pre F', 'announces F', 'senses F', 'suggests F', 'reveals GOAL' or an effect",
        )
    unbound = set(event.parameters) - _used(event)
    if unbound:
        raise comp.error(
            f"parameter '{sorted(unbound)[0]}' is not bound by the trigger",
            event.name,
            "the trigger says which robot or goal it is about (e.g. 'when r settles at g')",
        )


def _used(event: _Event) -> set[str]:
    trigger: Trigger = event.parts["trigger"]
    return {trigger.robot, trigger.target} - {None}


def _trigger(event: _Event, node: Tree) -> Trigger:
    comp, kind = event.comp, str(node.data)
    if kind == "at_step":
        step = comp.count(node.children[0], "steps", low=0)
        trigger = Trigger("step", value=step)
        comp.step_triggers.append((step, node.children[0]))  # checked against the step limit
    elif kind == "reached":
        trigger = Trigger("reached", target=event.name_of(node.children[0], "goal"))
    elif kind == "within":
        robot, distance, target = node.children
        trigger = Trigger(
            "within",
            event.name_of(robot, "robot"),
            event.name_of(target, "place"),
            comp.number(distance, 0.0),
        )
    else:
        robot, target = node.children
        trigger = Trigger(kind, event.name_of(robot, "robot"), event.name_of(target, "goal"))
    event.parts["trigger"] = trigger
    return trigger


def _fact(event: _Event, fml: Tree, sensed: bool) -> Formula:
    """A fact an event teaches: assigned(ROBOT, GOAL) and closed(GOAL) atoms; a sensed fact
    only closed(GOAL) (the simulator knows which goals are closed, not where robots go)."""
    comp = event.comp
    tree = fml.children[0]
    for node in tree.iter_subtrees_topdown():
        kind = node.data.rsplit("__", 1)[-1]
        if kind in ("agent", "action", "announce", "announce_diamond"):
            raise comp.error(
                "an event teaches a fact about the world, without K, B or actions",
                node,
                "use assigned(ROBOT, GOAL) and closed(GOAL) with ~, &, |, ->, <->",
            )
        if kind == "atom":
            stem, args = node.children
            arguments = [] if args is None else args.children
            if str(stem) == "closed" and len(arguments) == 1:
                event.name_of(arguments[0], "goal")
            elif str(stem) == "assigned" and len(arguments) == 2 and not sensed:
                event.name_of(arguments[0], "robot")
                event.name_of(arguments[1], "goal")
            else:
                expected = "closed(GOAL)" if sensed else "assigned(ROBOT, GOAL) or closed(GOAL)"
                raise comp.error(
                    f"'{stem}' is not a fact {'a robot can sense' if sensed else 'of missions'}",
                    stem,
                    f"use {expected}"
                    + ("; robots cannot sense where teammates will go" if sensed else ""),
                )
    return comp.build(fml)


def _observer(event: _Event, node: Tree) -> ObserverRule:
    who, fml = node.children
    comp = event.comp
    if str(who) != "robots":
        event.name_of(who, "robot")
    if fml is None:
        return ObserverRule(str(who))
    for sub in fml.children[0].iter_subtrees_topdown():
        kind = sub.data.rsplit("__", 1)[-1]
        if kind in ("agent", "action", "announce", "announce_diamond"):
            raise comp.error(
                "an observer condition speaks of the world, without K, B or actions",
                sub,
                "use sees(X), near(X, METRES), sensor(range|bearing) with ~, &, |",
            )
        if kind == "atom":
            _predicate(event, sub)
    return ObserverRule(str(who), comp.build(fml))


def _predicate(event: _Event, node: Tree) -> None:
    comp = event.comp
    stem, args = node.children
    arguments = [] if args is None else args.children
    arity = PREDICATES.get(str(stem))
    if arity is None or len(arguments) != arity:
        raise comp.error(
            f"'{stem}' is not a quantity the simulator has",
            stem,
            "observer conditions use sees(X), near(X, METRES) and sensor(range|bearing)",
        )
    if str(stem) == "sensor":
        if str(arguments[0]) not in ("range", "bearing"):
            raise comp.unknown("sensor", arguments[0], ("range", "bearing"))
        return
    if str(arguments[0]) != "reachers" or str(stem) != "sees":
        event.name_of(arguments[0], "place")
    if str(stem) == "near":
        comp.number(arguments[1], 0.0)
