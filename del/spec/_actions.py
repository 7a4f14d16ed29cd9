"""Compiling the actions of a spec file (and the relations shared with explicit models).

Helper of :mod:`epistemica.del_.spec._compiler`: for each action (schemas are expanded by
:func:`epistemica.del_.spec._names.headers`) it compiles one of the three action forms:

- a one-liner (``public F``, ``private F to G``, ``sense F by G``, ``assign p := F``) into
  the helpers of :mod:`epistemica.del_.explicit.action`;
- an observability block (``pre``, ``executable``, ``effect``, ``senses``/``announces``,
  ``full``, ``partial``, ``oblivious``) into
  :func:`epistemica.del_.explicit.observability.observability_action`;
- an explicit event model (``event``, ``relation``/``knowledge``/``partition``,
  ``designated``) into :class:`~epistemica.del_.explicit.action.ActionModel`.

The functions take the spec compiler as their first argument and raise its located
:class:`~epistemica.del_.errors.SpecError`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from lark import Token, Tree

from epistemica.del_.errors import EpistemicaError
from epistemica.del_.explicit import action as helpers
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.explicit.observability import observability_action
from epistemica.del_.language.formula import Formula, Top
from epistemica.del_.spec._names import names_hint

__all__ = ["compile_actions", "members", "owners", "relations"]

_OBSERVABILITY = {
    "pre", "effect_item", "senses", "announces", "executable", "full", "partial", "oblivious",
}  # fmt: skip
_EVENTS = {"event", "event_relation", "event_designated"}


def compile_actions(comp: Any, found: Mapping[str, tuple]) -> dict[str, Any]:
    """Compile every expanded action; see the module docstring for the three forms."""
    actions = {}
    for key, (decl, env) in found.items():
        name, _parameters, _owner, body = decl.children
        comp.action_name = str(name)
        comp.params = dict(env)
        try:
            actions[key] = _compile(comp, key, body, env, decl)
        finally:
            comp.params, comp.action_name = {}, ""
    return actions


def owners(comp: Any, found: Mapping[str, tuple]) -> dict[str, str]:
    """Action name -> owner, for the actions declared ``action NAME by AGENT``.

    The owner may be a parameter of a schema (``action go(i in agents) by i``).
    """
    table = {}
    for key, (decl, env) in found.items():
        owner = decl.children[2]
        if owner is not None:
            token = owner.children[0]
            comp.action_name, comp.params = str(decl.children[0]), dict(env)
            try:
                table[key] = comp.agent(env.get(str(token), str(token)), token)
            finally:
                comp.params, comp.action_name = {}, ""
    return table


def _compile(comp: Any, key: str, body: Tree, env: dict[str, str], decl: Tree) -> Any:
    agents = comp.names.agents
    kind = body.data
    try:
        if kind == "public":
            return helpers.public_announcement(comp.formula(body.children[0], env), agents)
        if kind in ("private", "sense"):
            f = comp.formula(body.children[0], env)
            observers = _agents(comp, body.children[1], env)
            make = (
                helpers.private_announcement if kind == "private" else helpers.semi_private_sensing
            )
            return make(f, observers, agents)
        if kind == "assign":
            effects, when = body.children
            pre = Top() if when is None else comp.formula(when, env)
            return helpers.public_assignment(_effects(comp, [effects], env), agents, pre=pre)
        items = [item for item in body.children if item is not None]
        kinds = {item.data for item in items}
        if kinds & _OBSERVABILITY and kinds & _EVENTS:
            odd = next(i for i in items if i.data in _EVENTS)
            raise comp.error(
                "an action mixes explicit events with observability lines", odd,
                "write either 'event'/'relation'/'designated' lines (an event model) or "
                "'pre'/'effect'/'full'/'partial'/'oblivious' lines, not both",
            )  # fmt: skip
        if kinds & _EVENTS:
            return _event_model(comp, items, env, decl)
        return _observability(comp, key, items, env)
    except EpistemicaError as exc:
        if getattr(exc, "line", None) is not None:
            raise
        raise comp.error(f"action '{key}': {exc.message}", decl, exc.hint) from None


def _agents(comp: Any, names: Tree, env: Mapping[str, str]) -> list[str]:
    return [comp.agent(n, t) for n, t in comp.expand(names, env)]


def _effects(comp: Any, nodes: list[Tree], env: Mapping[str, str]) -> dict[str, Formula]:
    found: dict[str, Formula] = {}
    for node in nodes:
        for effect in node.children:
            ref, fml = effect.children
            key, token = comp.atom_ref(ref, env)
            if key not in comp.names.atoms and ref.children[1] is not None:
                comp.unbound_argument(_tokens(ref.children[1]))
            comp.atom(key, token)
            if key in found:
                raise comp.error(f"'{key}' assigned twice", token, "keep one assignment")
            found[key] = comp.formula(fml, env)
    return found


def _tokens(tree: Tree) -> list[Token]:
    return list(tree.scan_values(lambda v: isinstance(v, Token)))


def _observability(comp: Any, key: str, items: list[Tree], env: dict[str, str]) -> Any:

    once: dict[str, Tree] = {}
    effects: list[Tree] = []
    roles: dict[str, dict[str, Any]] = {"full": {}, "partial": {}}
    placed: dict[str, Token] = {}

    def place(agent: str, token: Token) -> str:
        comp.agent(agent, token)
        if agent in placed:
            first = placed[agent]
            raise comp.error(
                f"agent '{agent}' is given two observabilities", token,
                f"already placed at {first.line}:{first.column}; list each agent once",
            )  # fmt: skip
        placed[agent] = token
        return agent

    for item in items:
        if item.data in ("pre", "senses", "announces", "executable"):
            outcome = item.data in ("senses", "announces")
            clash = once.get(item.data) or (
                outcome and (once.get("senses") or once.get("announces"))
            )
            if clash:
                raise comp.error(
                    f"a second '{item.data}' line", item,
                    "join the formulas with '&'; an action senses or announces one formula",
                )  # fmt: skip
            once[item.data] = item
        elif item.data == "effect_item":
            effects.append(item.children[0])
        elif item.data in roles:
            for observer in item.children[0].children:
                who, cond = observer.children
                agent = place(env.get(str(who), str(who)), who)
                roles[item.data][agent] = True if cond is None else comp.formula(cond, env)
        else:  # oblivious: the default, listed for the reader
            for agent, token in comp.expand(item.children[0], env):
                place(agent, token)

    def text(kind: str) -> Formula | None:
        return comp.formula(once[kind].children[0], env) if kind in once else None

    return observability_action(
        comp.names.agents,
        pre=text("pre") or Top(),
        effects=_effects(comp, effects, env) or None,
        senses=text("senses"),
        announces=text("announces"),
        full=roles["full"],
        partial=roles["partial"],
        name=key,
        executable=text("executable"),
    )


def _event_model(comp: Any, items: list[Tree], env: dict[str, str], decl: Tree) -> Any:

    events: dict[str, Token] = {}
    pre: dict[str, Formula] = {}
    post: dict[str, dict[str, Formula]] = {}
    for item in (i for i in items if i.data == "event"):
        name, *parts = (c for c in item.children if c is not None)
        if str(name) in events:
            first = events[str(name)]
            raise comp.error(
                f"event '{name}' declared twice", name,
                f"first declared at {first.line}:{first.column}; rename one",
            )  # fmt: skip
        events[str(name)] = name
        for part in parts:
            if part.data == "event_pre":
                if str(name) in pre:
                    raise comp.error("a second 'pre' for one event", part, "join them with '&'")
                pre[str(name)] = comp.formula(part.children[0], env)
            else:
                effects = _effects(comp, [part.children[0]], env)
                clash = set(effects) & set(post.get(str(name), {}))
                if clash:
                    raise comp.error(f"'{min(clash)}' assigned twice", part, "keep one")
                post.setdefault(str(name), {}).update(effects)
    stmts = [i for i in items if i.data == "event_relation"]
    rel, know = relations(comp, stmts, events, "event", conditions=True, env=env, where=decl)
    designated_items = [i for i in items if i.data == "event_designated"]
    if not designated_items:
        raise comp.error(
            "the event model has no 'designated' line", decl,
            "add 'designated e' naming the event(s) that actually happen",
        )  # fmt: skip
    designated = members(comp, designated_items, events, "event", env)
    return ActionModel(list(events), pre, post, rel, designated, knowledge=know)


def members(
    comp: Any, stmts: list[Tree], known: Mapping[str, Token], kind: str, env=None
) -> list[str]:
    """The names listed by ``designated`` statements, each checked against ``known``."""
    found: list[str] = []
    for stmt in stmts:
        for name, token in comp.expand(stmt.children[0], env or {}):
            if name not in known:
                raise comp.error(f"unknown {kind} '{name}'", token, names_hint(name, known, kind))
            if name not in found:
                found.append(name)
    return found


def relations(
    comp: Any,
    stmts: list[Tree],
    known: Mapping[str, Token],
    kind: str,
    conditions: bool,
    env: Mapping[str, str] | None = None,
    where: Tree | None = None,
) -> tuple[dict[str, list[tuple]], dict[str, list[tuple]] | None]:
    """Belief and knowledge relations (agent -> edges) from relation statements.

    ``relation``/``partition`` lines give the belief relation, ``knowledge`` lines a
    separate knowledge relation (agents without one reuse their belief relation). Edges
    ``x -> y``, ``x <-> y`` and blocks ``{x, y}`` (all pairs, loops included) may carry
    ``if F`` when ``conditions`` is true (event models).
    """
    env = env or {}
    belief: dict[str, list[tuple]] = {}
    knowledge: dict[str, list[tuple]] = {}
    covered: dict[str, dict[str, Token]] = {}
    for stmt in stmts:
        kind_node, names, edges = stmt.children
        relation_kind = str(kind_node.children[0])
        target = knowledge if relation_kind == "knowledge" else belief
        for agent in _agents(comp, names, env):
            pairs = target.setdefault(agent, [])
            for edge in edges.children:
                pairs.extend(_edge(comp, edge, known, kind, conditions, env))
                if relation_kind == "partition":
                    _cover(comp, edge, agent, covered.setdefault(agent, {}))
    for agent, seen in covered.items():
        missing = [name for name in known if name not in seen]
        if missing:
            raise comp.error(
                f"the partition of '{agent}' leaves out {kind} '{missing[0]}'", where or stmts[0],
                f"put every {kind} in one block, e.g. add {{{missing[0]}}}",
            )  # fmt: skip
    absent = [a for a in comp.names.agents if a not in belief]
    if absent:
        raise comp.error(
            f"agent '{absent[0]}' has no relation", where or (stmts[0] if stmts else None),
            f"add 'relation {absent[0]}: ...' or 'partition {absent[0]}: {{...}}' "
            f"(B[{absent[0]}] and K[{absent[0]}] quantify over it)",
        )  # fmt: skip
    if not knowledge:
        return belief, None
    return belief, {a: knowledge.get(a, belief[a]) for a in comp.names.agents}


def _edge(comp, edge: Tree, known, kind: str, conditions: bool, env) -> list[tuple]:
    *names, cond = edge.children
    for token in names:
        if str(token) not in known:
            raise comp.error(
                f"unknown {kind} '{token}'", token, names_hint(str(token), known, kind)
            )
    ends = [str(t) for t in names]
    if edge.data == "arrow":
        pairs = [(ends[0], ends[1])]
    elif edge.data == "both_ways":
        pairs = [(ends[0], ends[1]), (ends[1], ends[0])]
    else:
        pairs = [(x, y) for x in ends for y in ends]
    if cond is None:
        return pairs
    if not conditions:
        raise comp.error(
            "conditions on edges are allowed in event models only", cond,
            "an edge of a Kripke model is there or not; remove 'if ...'",
        )  # fmt: skip
    f = comp.formula(cond, env)
    return [(x, y, f) for x, y in pairs]


def _cover(comp, edge: Tree, agent: str, seen: dict[str, Token]) -> None:
    if edge.data != "block" or edge.children[-1] is not None:
        raise comp.error(
            "a partition is a list of blocks such as {w1, w2}, {w3}", edge,
            "use 'relation' for arrows and conditions",
        )  # fmt: skip
    for token in edge.children[:-1]:
        if str(token) in seen:
            first = seen[str(token)]
            raise comp.error(
                f"'{token}' is in two blocks of the partition of '{agent}'", token,
                f"first placed at {first.line}:{first.column}; blocks must not overlap",
            )  # fmt: skip
        seen[str(token)] = token
