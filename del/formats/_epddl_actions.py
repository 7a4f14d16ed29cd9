"""The ground actions of an EPDDL domain, as event models.

Helper of :mod:`epistemica.del_.formats.epddl`. Each binding of an action's parameters that
satisfies its condition is one :class:`~epistemica.del_.explicit.action.ActionModel`,
built from its action type (a library's ``:action-type``, or ``basic``: one event seen by
everyone) and the domain events passed to it, with plank's semantics:

- an event's postcondition of atom ``p``: with ``P`` the conditions under which the event
  makes ``p`` true and ``N`` those under which it makes it false (a literal effect has
  condition ``true``; ``(when c l)`` condition ``c``; ``(iff c l)`` makes ``l`` true under
  ``c`` and false under ``~c``), ``p := OR(P)`` when ``N`` is empty, ``p := p & ~OR(N)``
  when ``P`` is, and ``p := OR(P) | (p & ~OR(N))`` otherwise;
- each agent's observability type is decided **at the designated world** where the action
  happens: among the types whose condition holds there, the last one declared in the action
  type; the first type when none holds. Plank evaluates the conditions on the state and
  applies one relation per agent to the whole product update. A DEL event model evaluates
  conditions world by world, so an action whose types depend on the state is compiled into
  one copy of its events per assignment of types to agents: a designated copy of each
  designated event, whose precondition also says that the assignment is the one of the world
  where it happens, leading to a copy of every event with its own precondition, related as
  that assignment says. On single-pointed states (and on multi-pointed ones whose designated
  worlds agree on the conditions) the product update is plank's.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping

from lark import Token, Tree

from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.formats._epddl_formulas import conj, disj, negate
from epistemica.del_.formats._epddl_ground import MAX_GROUND, Grounder, plank_name
from epistemica.del_.formats._epddl_syntax import Source, mangle
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
    shared,
)

__all__ = ["MAX_ASSIGNMENTS", "ground_actions"]

#: Bound on the assignments of observability types to agents of one action.
MAX_ASSIGNMENTS = 4096

_BOOLEAN = (Not, And, Or, Implies, Iff)
# Observability conditions are tabulated over at most this many atoms and modal formulas.
_TRUTH_TABLE = 12

_CONDITIONS = {
    ":trivial-precondition", ":trivial-postconditions", ":trivial-event",
    ":non-trivial-precondition", ":non-trivial-postconditions", ":non-trivial-event",
    ":propositional-precondition", ":propositional-postconditions", ":propositional-event",
}  # fmt: skip


class _ActionType:
    """An action type: event variables, observability types, relations, designated events."""

    def __init__(self, g: Grounder, name: Token, src: Source | None, tree: Tree | None):
        self.name = str(name)
        if tree is None:  # 'basic': one event, one type, everyone sees it
            self.events, self.types = ["?e"], ["Fully"]
            self.relations = {"Fully": {("?e", "?e")}}
            self.designated, self.conditions = ["?e"], {}
            return
        _name, events, types, *rels, designated, conditions = tree.children
        self.events = [str(v) for v in events.children]
        self.types = [str(t) for t in types.children]
        local = {e: "event" for e in self.events}
        env = {e: e for e in self.events}
        self.relations: dict[str, set] = {t: set() for t in self.types}
        for rel in rels:
            tname, edges = rel.children
            if str(tname) not in self.relations:
                raise src.error(
                    f"unknown observability type '{tname}'", tname,
                    f"types of {self.name}: {', '.join(self.types)}",
                )  # fmt: skip
            pairs = set()
            for pair, here in g.list_items(edges, env, src, local=local):
                pairs.add(tuple(g.term(t, here, src, local) for t in pair.children))
            self.relations[str(tname)] = pairs  # a second list replaces the first, as in plank
        self.designated = []
        for d in designated.children:
            if str(d) not in self.events:
                raise src.error(f"unknown event '{d}'", d, f"events: {', '.join(self.events)}")
            self.designated.append(str(d))
        self.conditions = {}
        for node in conditions.children if conditions is not None else []:
            var, *words = node.children
            self.conditions[str(var)] = [str(w) for w in words]


def ground_actions(g: Grounder, initial) -> tuple[dict[str, ActionModel], dict[str, str]]:
    """Every ground action: epistemica name -> event model, and -> plank's name.

    ``initial`` is the initial model: atoms constant across it and changed only by
    one-event actions, as functions of such atoms, are the same in every world of every
    reachable state, so observability conditions over them need no copies (module
    docstring).
    """
    raw: dict[str, tuple] = {}
    plank: dict[str, str] = {}
    types: dict[str, _ActionType] = {}
    for decl in g.actions:
        name, comprehension, signature, observability = decl.children
        tname = signature.children[0]
        if str(tname) not in types:
            if str(tname) == "basic":
                types[str(tname)] = _ActionType(g, tname, None, None)
            elif str(tname) in g.action_types:
                tree, src = g.action_types[str(tname)]
                types[str(tname)] = _ActionType(g, tname, src, tree)
            else:
                raise g.dsrc.error(
                    f"unknown action type '{tname}'", tname,
                    "it must be defined in an action-type library given with -l (such as one "
                    "the domain names in (:action-type-libraries ...)), or be 'basic'",
                )  # fmt: skip
        kind = types[str(tname)]
        calls = signature.children[1:]
        if len(calls) != len(kind.events):
            raise g.dsrc.error(
                f"action type '{tname}' takes {len(kind.events)} events, found {len(calls)}",
                tname, f"its events: {' '.join(kind.events)}",
            )  # fmt: skip
        params = [str(v.children[0]) for v in comprehension.children[:-1]]
        for env in g.bindings(comprehension, {}, g.dsrc):
            values = [env[p] for p in params]
            key = mangle(str(name)) + (
                f"({', '.join(mangle(v) for v in values)})" if values else ""
            )
            raw[key] = (kind, *_action(g, kind, calls, observability, env), name)
            plank[key] = plank_name(str(name), values)
            if len(raw) > MAX_GROUND:
                raise g.dsrc.error(f"more than {MAX_GROUND} ground actions", name, "fewer objects")
    public = _public_atoms(initial, [(k, post) for k, _, post, _, _ in raw.values()])
    actions = {
        key: _event_model(g, kind, pre, post, obs, key, public, where)
        for key, (kind, pre, post, obs, where) in raw.items()
    }
    return actions, plank


def _public_atoms(initial, actions: list) -> frozenset[str]:
    """Atoms with one value in every world of every reachable state.

    Sufficient condition, to a fixpoint: constant across the initial model, and set only
    by one-event actions (every product world then takes the same event) to a
    propositional function of such atoms.
    """
    values = initial.valuation
    constant = values.all(axis=0) | ~values.any(axis=0)
    public = {a for a, c in zip(initial.atoms, constant, strict=True) if c}
    changed = True
    while changed:
        changed = False
        for kind, post in actions:
            for table in post.values():
                for atom, f in table.items():
                    if atom not in public:
                        continue
                    if len(kind.events) > 1 or not _over(f, public):
                        public.discard(atom)
                        changed = True
    return frozenset(public)


def _over(f: Formula, atoms) -> bool:
    """Whether ``f`` is propositional over ``atoms``."""
    return all(
        isinstance(g, (Top, Bottom, *_BOOLEAN)) or (isinstance(g, Atom) and g.key in atoms)
        for g in f.subformulas()
    )


def _action(g: Grounder, kind: _ActionType, calls, observability, env) -> tuple:
    src = g.dsrc
    pre: dict[str, Formula] = {}
    post: dict[str, dict[str, Formula]] = {}
    for var, call in zip(kind.events, calls, strict=True):
        ename, *args = call.children
        if str(ename) not in g.events:
            raise src.error(f"unknown event '{ename}'", ename, f"events: {', '.join(g.events)}")
        event = g.events[str(ename)]
        _check_conditions(src, kind, var, event, ename)
        pre[var], post[var] = _event(g, event, [g.term(a, env, src) for a in args], ename, env)
    return pre, post, _observability(g, kind, observability, env)


def _event(g: Grounder, event: Tree, values: list[str], call: Token, outer: dict):
    src = g.dsrc
    ename, params, precondition, effects = event.children
    formal = [] if params is None else [str(v.children[0]) for v in params.children]
    typed = [] if params is None else g.typed_vars(params.children, src)
    if len(values) != len(formal):
        raise src.error(
            f"event '{ename}' takes {len(formal)} argument{'s' * (len(formal) != 1)}, found "
            f"{len(values)}", call, f"declared at {ename.line}:{ename.column}",
        )  # fmt: skip
    for value, (token, wanted) in zip(values, typed, strict=True):
        if not g.is_a(g.entities[value], wanted):
            raise src.error(
                f"'{value}' is not of type {' or '.join(sorted(wanted))}", call,
                f"parameter {token} of event '{ename}'",
            )  # fmt: skip
    # plank looks a variable up in the outermost binding first: an action parameter
    # shadows an event parameter of the same name (docs/epddl.md, "Scopes").
    env = {**dict(zip(formal, values, strict=True)), **outer}
    pre = Top() if precondition is None else g.formula(precondition, env, src)
    if effects is None or effects.children[0] is None:
        return pre, {}
    true_when: dict[str, list[Formula]] = {}
    false_when: dict[str, list[Formula]] = {}
    for node, here in g.list_items(effects.children[0], env, src):
        if node.data in ("positive", "negative"):
            literals, cond, both = [(node, here)], Top(), False
        else:
            cond_tree, literal_list = node.children
            cond = g.formula(cond_tree, here, src)
            literals, both = g.list_items(literal_list, here, src), node.data == "iff"
        for literal, at in literals:
            name, *args = literal.children
            _, is_fact, _ = g.predicate(name, args, src)
            if is_fact:
                raise src.error(
                    f"an effect on the fact '{name}'", name, "facts never change; drop :fact"
                )
            atom = g.atom_of(str(name), g.check_args(name, args, at, src)).key
            positive = literal.data == "positive"
            (true_when if positive else false_when).setdefault(atom, []).append(cond)
            if both:
                (false_when if positive else true_when).setdefault(atom, []).append(negate(cond))
            else:
                (false_when if positive else true_when).setdefault(atom, [])
    post = {}
    for atom in dict.fromkeys([*true_when, *false_when]):
        on, off = true_when.get(atom, []), false_when.get(atom, [])
        keep = conj([g.atom_formula(atom), negate(disj(off))])
        post[atom] = disj(on) if not off else (keep if not on else disj([disj(on), keep]))
    return pre, post


def _check_conditions(src: Source, kind: _ActionType, var: str, event: Tree, call: Token) -> None:
    _, _, precondition, effects = event.children
    trivial_pre = precondition is None or precondition.children[0].data == "top"
    trivial_post = effects is None or effects.children[0] is None
    modal_pre = precondition is not None and any(
        t.data in ("box", "diamond") for t in precondition.iter_subtrees()
    )
    modal_post = effects is not None and any(
        t.data in ("box", "diamond") for t in effects.iter_subtrees()
    )
    for word in kind.conditions.get(var, []):
        bad = {
            ":trivial-precondition": not trivial_pre,
            ":non-trivial-precondition": trivial_pre,
            ":trivial-postconditions": not trivial_post,
            ":non-trivial-postconditions": trivial_post,
            ":trivial-event": not (trivial_pre and trivial_post),
            ":non-trivial-event": trivial_pre and trivial_post,
            ":propositional-precondition": modal_pre,
            ":propositional-postconditions": modal_post,
            ":propositional-event": modal_pre or modal_post,
        }[word]
        if bad:
            raise src.error(
                f"event '{call}' passed as {var} of '{kind.name}' violates {word}", call,
                f"action type '{kind.name}' requires {var} to satisfy {word}",
            )  # fmt: skip


def _observability(g: Grounder, kind: _ActionType, tree, env) -> dict[str, dict[int, Formula]]:
    """Agent -> {type index: condition}, as plank assigns them."""
    src = g.dsrc
    table: dict[str, dict[int, Formula]] = {a: {} for a in g.agents}
    if tree is None:
        return {a: {0: Top()} for a in g.agents}
    index = {t: i for i, t in enumerate(kind.types)}
    default = None

    def type_of(token: Token) -> int:
        if str(token) not in index:
            raise src.error(
                f"unknown observability type '{token}'", token,
                f"types of '{kind.name}': {', '.join(kind.types)}",
            )  # fmt: skip
        return index[str(token)]

    def assign(agent: str, t: int, cond: Formula, where) -> None:
        old = table[agent].get(t)
        if old is not None and old != cond:
            raise src.error(
                f"agent '{agent}' is given type {kind.types[t]} twice", where,
                "give each agent each type once",
            )  # fmt: skip
        table[agent][t] = cond

    for node, here in g.list_items(tree.children[0], env, src):
        if node.data == "default_obs":
            default = type_of(node.children[0])
            continue
        agent = g.term(node.children[0], here, src)
        if g.entities.get(agent) != "agent":
            raise src.error(f"'{agent}' is not an agent", node.children[0], ", ".join(g.agents))
        if node.data == "static_obs":
            assign(agent, type_of(node.children[1]), Top(), node)
            continue
        _, cond, tname, *rest = node.children
        c = g.formula(cond, here, src)
        assign(agent, type_of(tname), c, node)
        previous = [negate(c)]
        otherwise = None
        for branch in rest:
            if branch is None:
                continue
            if branch.data == "else_if":
                c2 = g.formula(branch.children[0], here, src)
                assign(agent, type_of(branch.children[1]), conj([*previous, c2]), branch)
                previous.append(negate(c2))
            else:
                otherwise = type_of(branch.children[0])
        fallback = otherwise if otherwise is not None else default
        if fallback is not None:
            assign(agent, fallback, conj(previous), node)
    for agent, conds in table.items():
        if not conds:
            if default is None:
                raise src.error(
                    f"no observability condition for agent '{agent}'", tree,
                    "add (default TYPE) or a condition for every agent",
                )  # fmt: skip
            conds[default] = Top()
    return table


def _selectors(conds: Mapping[int, Formula]) -> dict[int, Formula]:
    """Per type, the condition under which plank picks it: the last type whose condition
    holds, the first type when none does."""
    order = sorted(conds)
    out = {}
    for k, t in enumerate(order):
        out[t] = conj([conds[t], *(negate(conds[u]) for u in order[k + 1 :])])
    none = conj(negate(conds[t]) for t in order)
    out[0] = disj([out[0], none]) if 0 in out else none
    # The usual case, exclusive and exhaustive conditions (if ... else ...): keep them.
    return {
        t: conds[t] if t in conds and equivalent(f, conds[t]) else f
        for t, f in out.items()
        if satisfiable(f)
    }


def equivalent(f: Formula, g: Formula) -> bool:
    """Whether ``f`` and ``g`` are equivalent as Boolean formulas (see :func:`satisfiable`)."""
    return not satisfiable(Or(And(f, negate(g)), And(negate(f), g)))


def satisfiable(f: Formula) -> bool:
    """Whether ``f`` is satisfiable as a Boolean formula over its atoms and its maximal
    modal subformulas (taken as independent atoms): ``False`` proves it unsatisfiable."""
    opaque: dict[Formula, int] = {}
    stack = [f]
    while stack:
        g = stack.pop()
        if isinstance(g, (Top, Bottom)):
            continue
        if isinstance(g, _BOOLEAN):
            stack.extend(g.children())
        elif g not in opaque:
            opaque[g] = len(opaque)
    if len(opaque) > _TRUTH_TABLE:
        return True  # too many to tabulate: assume satisfiable (a copy too many is harmless)
    for bits in range(1 << len(opaque)):
        if _truth(f, opaque, bits):
            return True
    return False


def _truth(f: Formula, opaque: dict[Formula, int], bits: int) -> bool:
    if isinstance(f, Top):
        return True
    if isinstance(f, Bottom):
        return False
    if isinstance(f, Not):
        return not _truth(f.operand, opaque, bits)
    if isinstance(f, And):
        return _truth(f.left, opaque, bits) and _truth(f.right, opaque, bits)
    if isinstance(f, Or):
        return _truth(f.left, opaque, bits) or _truth(f.right, opaque, bits)
    if isinstance(f, Implies):
        return not _truth(f.left, opaque, bits) or _truth(f.right, opaque, bits)
    if isinstance(f, Iff):
        return _truth(f.left, opaque, bits) == _truth(f.right, opaque, bits)
    return bool(bits >> opaque[f] & 1)


def _event_model(g: Grounder, kind, pre, post, types, key: str, public, where) -> ActionModel:
    options = {a: _selectors(types[a]) for a in g.agents}
    static = {a: next(iter(o)) for a, o in options.items() if len(o) == 1}
    dynamic = [a for a in g.agents if a not in static]
    if all(_over(f, public) for a in dynamic for f in options[a].values()):
        # The conditions have one value across each reachable state: conditioned edges.
        return _conditioned_model(g, kind, pre, post, static, options)
    total = 1
    for a in dynamic:
        total *= len(options[a])
    if total > MAX_ASSIGNMENTS:
        raise g.dsrc.error(
            f"action '{key}' has {total} assignments of observability types to agents, more "
            f"than {MAX_ASSIGNMENTS}", where, "make more observability conditions static",
        )  # fmt: skip
    events: list[str] = []
    pres: dict[str, Formula] = {}
    posts: dict[str, dict] = {}
    rel: dict[str, list[tuple[str, str]]] = {mangle(a): [] for a in g.agents}
    designated: list[str] = []
    assignments = list(itertools.product(*(sorted(options[a].items()) for a in dynamic)))
    for k, choice in enumerate(assignments):
        chosen = dict(static)
        chosen.update({a: t for a, (t, _) in zip(dynamic, choice, strict=True)})
        guard = conj(f for _, f in choice)
        suffix = f"/{k}" if len(assignments) > 1 else ""
        inner = {v: v[1:] + suffix for v in kind.events}
        outer = {v: v[1:] + suffix + "*" for v in kind.designated} if dynamic else inner
        for v in kind.events:
            events.append(inner[v])
            pres[inner[v]], posts[inner[v]] = pre[v], post[v]
        if dynamic:
            for v in kind.designated:
                events.append(outer[v])
                pres[outer[v]], posts[outer[v]] = conj([pre[v], guard]), post[v]
        designated += [outer[v] for v in kind.designated]
        for agent in g.agents:
            out = rel[mangle(agent)]
            for e, f in kind.relations[kind.types[chosen[agent]]]:
                out.append((inner[e], inner[f]))
                if dynamic and e in outer:
                    out.append((outer[e], inner[f]))
    return _shared_model(g, events, pres, posts, rel, designated)


def _conditioned_model(g: Grounder, kind, pre, post, static, options) -> ActionModel:
    names = {v: v[1:] for v in kind.events}
    rel: dict[str, list[tuple]] = {}
    for agent in g.agents:
        edges = []
        choices = {static[agent]: Top()} if agent in static else options[agent]
        for t, cond in choices.items():
            for e, f in sorted(kind.relations[kind.types[t]]):
                edges.append((names[e], names[f], cond))
        rel[mangle(agent)] = edges
    return _shared_model(
        g,
        [names[v] for v in kind.events],
        {names[v]: pre[v] for v in kind.events},
        {names[v]: post[v] for v in kind.events},
        rel,
        [names[v] for v in kind.designated],
    )


def _shared_model(g: Grounder, events, pres, posts, rel, designated) -> ActionModel:
    """The event model, its formulas shared with the task's other ground actions: equal
    conditions are one object, which the checker's memo finds without comparing trees."""

    def share(f):
        return shared(f, g.formulas) if isinstance(f, Formula) else f

    return ActionModel(
        events,
        {e: share(f) for e, f in pres.items()},
        {e: {atom: share(f) for atom, f in post.items()} for e, post in posts.items()},
        {a: [tuple(share(part) for part in edge) for edge in edges] for a, edges in rel.items()},
        designated,
    )
