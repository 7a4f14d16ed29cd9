"""Grounding EPDDL: types, entities, predicates, list comprehensions and formulas.

Helper of :mod:`epistemica.del_.formats.epddl`. :class:`Grounder` collects the declarations
of a domain, a problem and the action-type libraries the domain includes (parse trees of
:mod:`~epistemica.del_.formats._epddl_syntax`), and grounds what refers to them: a typed
list of variables into its bindings, a formula under a binding into a
:class:`~epistemica.del_.language.formula.Formula` over ground atoms. The semantics is the
one of the plank toolkit's grounder: facts (``:fact`` predicates) are constants fixed by
``:facts-init``; ``[i] f`` quantifies over agent i's one relation (``B[i]``); ``[G] f``
over each agent of G, ``<G> f`` is ``<i> f`` for each i of G (not the dual of ``[G]``);
``Kw.`` is "believes whether"; ``C.`` common belief; ``forall``/``exists`` range over the
bindings of their list comprehension. The initial state and the actions are built by
:mod:`~epistemica.del_.formats._epddl_state` and :mod:`~epistemica.del_.formats._epddl_actions`.

EPDDL names may contain ``-``, epistemica's may not: every name is written with ``_`` for
``-`` (``has-key`` becomes ``has_key``); two names that would collide are an error.
"""

from __future__ import annotations

import difflib
import itertools
from collections.abc import Iterable, Iterator, Mapping
from typing import Any

from lark import Token, Tree

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.formats._epddl_formulas import ground_formula, static_truth
from epistemica.del_.formats._epddl_syntax import Source, mangle
from epistemica.del_.language.formula import (
    Atom,
    Bottom,
    Formula,
    Top,
)

__all__ = ["MAX_GROUND", "Grounder", "plank_name"]

#: Bound on the bindings of one list and on the ground atoms of a task.
MAX_GROUND = 1_000_000

_BUILTIN = {"entity": None, "object": "entity", "agent": "entity", "agent-group": "entity",
            "world": None, "event": None, "obs-type": None}  # fmt: skip
_MODAL = {"box", "diamond"}


def plank_name(action: str, args: Iterable[str]) -> str:
    """The name plank gives a ground action: ``tell`` with ``C, A`` is ``tell_C_A``."""
    return "_".join([action, *args])


class _Terms:
    """Grounding what uses a task's declarations: typed variables, terms, agent lists and
    list comprehensions, bindings, predicates and atoms. :class:`Grounder` collects the
    declarations (``types``, ``entities``, ``agents``, ``groups``, ``predicates``) these
    methods read."""

    def typed_vars(
        self, nodes: list[Tree], src: Source, default: str = "object"
    ) -> list[tuple[Token, frozenset]]:
        out: list[tuple[Token, frozenset]] = []
        pending: list[Token] = []
        for node in nodes:
            token, kind = node.children
            pending.append(token)
            if kind is not None:
                names = [kind] if isinstance(kind, Token) else list(kind.children)
                for n in names:
                    if str(n) not in self.types:
                        raise src.error(f"unknown type '{n}'", n, self.type_hint(str(n)))
                out += [(t, frozenset(map(str, names))) for t in pending]
                pending = []
        return out + [(t, frozenset([default])) for t in pending]

    def type_hint(self, name: str) -> str:
        user = [t for t in self.types if _BUILTIN.get(t, 0) == 0]
        return f"declare it in (:types ...); types: {', '.join(user + list(_BUILTIN))}"

    # -- entities and terms ----------------------------------------------------------------

    def is_a(self, kind: str, wanted: frozenset) -> bool:
        while kind is not None:
            if kind in wanted:
                return True
            kind = self.types.get(kind)
        return False

    def domain_of(self, wanted: frozenset, local: Mapping[str, str]) -> list[str]:
        """The entities (and local ones: worlds, events) of one of the types ``wanted``."""
        if not local:
            if wanted not in self._domains:
                self._domains[wanted] = [
                    e for e, k in self.entities.items() if self.is_a(k, wanted)
                ]
            return self._domains[wanted]
        return [e for e, k in itertools.chain(self.entities.items(), local.items())
                if self.is_a(k, wanted)]  # fmt: skip

    def term(self, token: Token, env: Mapping[str, str], src: Source, local=None) -> str:
        """The entity a term names: a variable's binding, or a declared name."""
        text = str(token)
        if token.type == "VARIABLE":
            if text not in env:
                raise src.error(
                    f"unbound variable '{text}'", token,
                    f"bound here: {', '.join(env) or 'none'}; declare it in :parameters or in "
                    "a forall/exists",
                )  # fmt: skip
            return env[text]
        if text not in self.entities and text not in self.groups and text not in (local or {}):
            raise src.error(f"unknown name '{text}'", token, _closest(text, self.entities))
        return text

    def agent_list(self, node: Any, env: Mapping[str, str], src: Source) -> list[str]:
        """The agents of a modality index or an agent list, groups expanded."""
        found: list[str] = []
        if isinstance(node, Token):
            if node.type == "ALL":
                return list(self.agents)
            terms = [node]
        elif node.data == "group":
            terms = list(node.children)
        else:  # a group_list: a list of groups
            for group in self.list_items(node.children[0], env, src):
                found += [a for a in group if a not in found]
            return found
        for token in terms:
            name = self.term(token, env, src)
            members = self.groups.get(name, [name])
            for agent in members:
                if self.entities.get(agent) != "agent":
                    raise src.error(
                        f"'{name}' is not an agent", token, f"agents: {', '.join(self.agents)}"
                    )
                if agent not in found:
                    found.append(agent)
        return found

    def list_items(self, tree: Tree, env: Mapping[str, str], src: Source, local=None) -> list:
        """The elements of an EPDDL list (``list{...}``) with their bindings.

        Each element is returned as ``(node, env)``, except for agent groups (``group``
        nodes), which are returned as their agents.
        """
        out: list = []
        stack: list[tuple[Any, Mapping[str, str]]] = [(tree, env)]
        while stack:
            node, here = stack.pop()
            if node is None:
                continue
            if node.data == "list":
                stack.append((node.children[0], here))
            elif node.data == "and_list":
                stack.extend((child, here) for child in reversed(node.children))
            elif node.data == "forall_list":
                comprehension, inner = node.children
                bindings = list(self.bindings(comprehension, here, src, local=local))
                stack.extend((inner, b) for b in reversed(bindings))
            elif node.data == "list_body":
                element = node.children[0]
                if isinstance(element, Tree) and element.data == "group":
                    out.append(self.agent_list(element, here, src))
                else:
                    out.append((element, here))
            else:  # pragma: no cover - the grammar has no other list node
                raise AssertionError(node.data)
        return out

    def bindings(
        self, comprehension: Tree, env: Mapping[str, str], src: Source, local=None,
        default: str = "object",
    ) -> Iterator[dict[str, str]]:  # fmt: skip
        """The bindings of a list comprehension ``?x ?y - t | condition``, extending ``env``."""
        *params, condition = comprehension.children
        typed = self.typed_vars(params, src, default)
        domains = []
        for token, wanted in typed:
            if str(token) in env:
                raise src.error(
                    f"variable '{token}' is already bound", token, "rename the inner variable"
                )
            domains.append(self.domain_of(wanted, local or {}))
        size = 1
        for d in domains:
            size *= len(d)
        if size > MAX_GROUND:
            raise src.error(
                f"the list has {size} bindings, more than {MAX_GROUND}", comprehension,
                "restrict it with a condition or fewer variables",
            )  # fmt: skip
        names = [str(t) for t, _ in typed]
        for values in itertools.product(*domains):
            bound = {**env, **dict(zip(names, values, strict=True))}
            if condition is None or self.static_truth(condition, bound, src, local):
                yield bound

    # -- predicates and atoms ----------------------------------------------------------------

    def predicate(self, name: Token, args: list, src: Source) -> tuple[list, bool, Token]:
        if str(name) not in self.predicates:
            raise src.error(
                f"unknown predicate '{name}'", name, _closest(str(name), self.predicates)
            )
        types, is_fact, decl = self.predicates[str(name)]
        if len(args) != len(types):
            raise src.error(
                f"'{name}' takes {len(types)} argument{'s' * (len(types) != 1)}, found "
                f"{len(args)}", name, f"declared at {decl.line}:{decl.column}",
            )  # fmt: skip
        return types, is_fact, decl

    def check_args(self, name: Token, args: list, env: Mapping[str, str], src: Source, local=None):
        types, _, _ = self.predicates[str(name)]
        values = []
        for token, wanted in zip(args, types, strict=True):
            value = self.term(token, env, src, local)
            kind = self.entities.get(value) or (local or {}).get(value)
            if kind is None or not self.is_a(kind, wanted):
                raise src.error(
                    f"'{value}' is not of type {' or '.join(sorted(wanted))}", token,
                    f"argument of predicate '{name}'",
                )  # fmt: skip
            values.append(value)
        return tuple(values)

    def atom(self, name: Token, args: list, env: Mapping[str, str], src: Source) -> Formula:
        """A ground predicate: a constant for a fact, else its :class:`Atom`."""
        _, is_fact, _ = self.predicate(name, args, src)
        values = self.check_args(name, args, env, src)
        if is_fact:
            return Top() if (str(name), values) in self.facts else Bottom()
        return self.atom_of(str(name), values)

    def atom_of(self, name: str, values: tuple[str, ...]) -> Atom:
        try:
            return Atom(mangle(name), tuple(mangle(v) for v in values))
        except InvalidArgumentError as exc:
            raise self.dsrc.error(exc.message, self.predicates[name][2], exc.hint) from None

    def atom_formula(self, key: str) -> Atom:
        """The :class:`Atom` of a ground atom's key (``at(A, room1)``)."""
        return self._atoms_by_key[key]

    def formula(self, tree: Tree, env: Mapping[str, str], src: Source) -> Formula:
        """The ground :class:`Formula` of a ``formula`` (or body) node under ``env``."""
        return ground_formula(self, tree, env, src)

    def static_truth(self, tree: Tree, env: Mapping[str, str], src: Source, local=None) -> bool:
        """Truth of a list-comprehension condition: facts, ``=``, ``/=`` and connectives."""
        return static_truth(self, tree, env, src, local)


class Grounder(_Terms):
    """The declarations of one EPDDL task and the grounding of what uses them.

    Parameters
    ----------
    domain, problem : tuple of (Tree, Source)
        The parse trees of the domain and the problem, with their texts.
    libraries : list of (Tree, Source)
        The action-type libraries given; the domain uses those it names.
    """

    def __init__(self, domain: tuple[Tree, Source], problem: tuple[Tree, Source], libraries):
        self.domain, self.dsrc = domain
        self.problem, self.psrc = problem
        self.types: dict[str, str | None] = dict(_BUILTIN)
        self.entities: dict[str, str] = {}  # EPDDL name -> primitive type
        self.agents: list[str] = []
        self.groups: dict[str, list[str]] = {}
        self.predicates: dict[str, tuple[list[frozenset], bool, Token]] = {}
        self.events: dict[str, Tree] = {}
        self.actions: list[Tree] = []
        self.action_types: dict[str, tuple[Tree, Source]] = {}
        self.facts: set[tuple[str, tuple[str, ...]]] = set()
        self.names: dict[str, str] = {}  # epistemica name of an entity -> its EPDDL name
        # One object per distinct formula of the ground actions (language.formula.shared).
        self.formulas: dict[Formula, Formula] = {}
        self._domains: dict[frozenset, list[str]] = {}
        self._atoms_by_key: dict[str, Atom] = {}
        self._collect_domain()
        self._collect_libraries(libraries)
        self._collect_problem()
        self.atoms = self._ground_atoms()

    # -- declarations ------------------------------------------------------------------

    def _collect_domain(self) -> None:
        _name, *items = self.domain.children
        for item in items:
            kind = item.data
            if kind == "types":
                for token, parent in self._typed(item.children, "object", self.dsrc):
                    if str(token) in self.types:
                        raise self.dsrc.error(f"type '{token}' declared twice", token, "rename it")
                    self.types[str(token)] = parent
            elif kind == "predicates":
                for decl in item.children:
                    fact, pname, *params = decl.children
                    if str(pname) in self.predicates:
                        raise self.dsrc.error(
                            f"predicate '{pname}' declared twice", pname, "keep one declaration"
                        )
                    types = [t for _, t in self.typed_vars(params, self.dsrc)]
                    self.predicates[str(pname)] = (types, fact is not None, pname)
            elif kind == "constants":
                self._declare_entities(item.children, self.dsrc)
            elif kind == "event":
                ename = item.children[0]
                if str(ename) in self.events:
                    raise self.dsrc.error(f"event '{ename}' declared twice", ename, "rename one")
                self.events[str(ename)] = item
            elif kind == "action":
                if any(str(a.children[0]) == str(item.children[0]) for a in self.actions):
                    raise self.dsrc.error(
                        f"action '{item.children[0]}' declared twice", item.children[0],
                        "rename one",
                    )  # fmt: skip
                self.actions.append(item)
        for token, parent in list(self._type_parents()):
            if parent is not None and parent not in self.types:
                raise self.dsrc.error(f"unknown type '{parent}'", token, self.type_hint(parent))

    def _type_parents(self) -> Iterator[tuple[Token, str | None]]:
        for item in self.domain.children[1:]:
            if item.data == "types":
                for node in item.children:
                    yield node.children[0], node.children[1] and str(node.children[1])

    def _collect_libraries(self, libraries) -> None:
        """The action types of every library given. As plank: the libraries the domain
        names must be among them, two libraries may not share a name, nor two action types
        (``basic`` included): which one was meant is not for the reader to guess."""
        wanted: dict[str, Token] = {}
        for item in self.domain.children[1:]:
            if item.data == "libraries":
                for token in item.children:
                    wanted[str(token)] = token
        given = {}
        for tree, src in libraries:
            if tree.data != "library":
                raise src.error(
                    f"expected an action-type library, found a {tree.data}", tree,
                    "pass libraries with -l; the domain and problem come first",
                )  # fmt: skip
            name = tree.children[0]
            if str(name) in given:
                first, first_src = given[str(name)]
                raise src.error(
                    f"a second action-type library named '{name}'", name,
                    f"the first is at {_where(first_src, first.children[0])}; pass one of them",
                )  # fmt: skip
            given[str(name)] = (tree, src)
        for name, token in wanted.items():
            if name not in given:
                raise self.dsrc.error(
                    f"action-type library '{name}' is not given", token,
                    "pass the file that defines it, e.g. -l libraries/" + name + ".epddl",
                )  # fmt: skip
        order = [*wanted, *(name for name in given if name not in wanted)]
        for name in order:
            tree, src = given[name]
            for item in tree.children[1:]:
                if item.data == "action_type":
                    self._add_action_type(item, src)

    def _add_action_type(self, item: Tree, src: Source) -> None:
        name = item.children[0]
        if str(name) == "basic":
            raise src.error(
                "the action type 'basic' is built in (one event seen by every agent)", name,
                "rename this action type",
            )  # fmt: skip
        if str(name) in self.action_types:
            first, first_src = self.action_types[str(name)]
            raise src.error(
                f"action type '{name}' is defined twice", name,
                f"the first definition is at {_where(first_src, first.children[0])}; "
                "rename one of them",
            )  # fmt: skip
        self.action_types[str(name)] = (item, src)

    def _collect_problem(self) -> None:
        _name, domain_name, *items = self.problem.children
        if str(domain_name) != str(self.domain.children[0]):
            raise self.psrc.error(
                f"the problem is for domain '{domain_name}', the domain given is "
                f"'{self.domain.children[0]}'", domain_name, "pass the matching domain file",
            )  # fmt: skip
        for item in items:
            if item.data == "objects":
                self._declare_entities(item.children, self.psrc)
            elif item.data == "agents":
                self._declare_entities(item.children, self.psrc, default="agent")
        self.agents = [e for e, t in self.entities.items() if t == "agent"]
        if not self.agents:
            raise self.psrc.error(
                "the task has no agents", self.problem, "declare them: (:agents A B)"
            )
        for item in items:
            if item.data == "agent_groups":
                for decl in item.children:
                    gname, _gtype, members = decl.children
                    if str(gname) in self.groups or str(gname) in self.entities:
                        raise self.psrc.error(f"'{gname}' declared twice", gname, "rename it")
                    agents = self.agent_list(members, {}, self.psrc)
                    self.groups[str(gname)] = agents
            elif item.data == "facts_init":
                for fact in item.children:
                    pname, *args = fact.children
                    _, is_fact, _ = self.predicate(pname, args, self.psrc)
                    if not is_fact:
                        raise self.psrc.error(
                            f"'{pname}' is not a fact", pname,
                            "only predicates declared (:fact ...) are initialised in "
                            ":facts-init; give the others in :init",
                        )  # fmt: skip
                    self.facts.add((str(pname), self.check_args(pname, args, {}, self.psrc)))

    def _declare_entities(self, nodes: list[Tree], src: Source, default: str = "object") -> None:
        for token, kind in self._typed(nodes, default, src):
            if kind is None or kind not in self.types:
                raise src.error(f"unknown type '{kind}'", token, self.type_hint(kind or ""))
            if str(token) in self.entities:
                raise src.error(f"'{token}' declared twice", token, "remove one declaration")
            self.entities[str(token)] = kind
            self._name(str(token), token, src)
            self._domains.clear()

    def _name(self, epddl: str, token: Token, src: Source) -> str:
        name = mangle(epddl)
        if self.names.setdefault(name, epddl) != epddl:
            raise src.error(
                f"'{epddl}' and '{self.names[name]}' both read as '{name}'", token,
                "epistemica writes '-' as '_'; rename one of them",
            )  # fmt: skip
        return name

    @staticmethod
    def _typed(nodes: list[Tree], default: str, src: Source) -> list[tuple[Token, str | None]]:
        """``a b - t c``: each name takes the type written after it (PDDL style)."""
        out: list[tuple[Token, str | None]] = []
        pending: list[Token] = []
        for node in nodes:
            token, kind = node.children
            pending.append(token)
            if kind is not None:
                out += [(t, str(kind)) for t in pending]
                pending = []
        return out + [(t, default) for t in pending]

    def _ground_atoms(self) -> list[str]:
        atoms: list[str] = []
        stems: dict[str, str] = {}
        for name, (types, is_fact, token) in self.predicates.items():
            if stems.setdefault(mangle(name), name) != name:
                raise self.dsrc.error(
                    f"predicates '{name}' and '{stems[mangle(name)]}' both read as "
                    f"'{mangle(name)}'", token, "epistemica writes '-' as '_'; rename one",
                )  # fmt: skip
            if is_fact:
                continue
            for values in itertools.product(*(self.domain_of(t, {}) for t in types)):
                atom = self.atom_of(name, values)
                self._atoms_by_key[atom.key] = atom
                atoms.append(atom.key)
                if len(atoms) > MAX_GROUND:
                    raise self.dsrc.error(
                        f"more than {MAX_GROUND} ground atoms", token,
                        "use fewer objects or :fact predicates for what never changes",
                    )  # fmt: skip
        return atoms

    # -- formulas ------------------------------------------------------------------------------


def _closest(name: str, known: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(known), n=1)
    if close:
        return f"did you mean '{close[0]}'?"
    return "declare it first (:objects, :agents, :constants or :predicates)"


def _where(src: Source, token: Token) -> str:
    """``file:line:col`` of ``token`` in ``src``, for a hint that points at a first definition."""
    return f"{src.filename}:{token.line}:{token.column}"
