"""What of a planning problem matters to its goal: the atoms and agents the goal and the
actions mention, the part of a model they see, and models projected onto them.

Split from :mod:`epistemica.del_.planning.planner` (which re-exports the public names):
the planners shrink each problem to its relevant part before searching.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from epistemica.del_.explicit._cube import Cube, pack_bits
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.explicit.bisimulation import generated_submodel
from epistemica.del_.language.formula import Formula
from epistemica.del_.language.modalities import Common, Distributed, Everybody, Know, KnowWhether
from epistemica.del_.language.parser import as_formula
from epistemica.del_.models import KripkeModel

__all__ = [
    "action_with_agents",
    "forget_knowledge",
    "project",
    "relevant_agents",
    "relevant_atoms",
    "relevant_part",
    "uses_distributed",
    "uses_knowledge",
]

_KNOWLEDGE_NODES = (Know, KnowWhether, Everybody, Common, Distributed)


def uses_knowledge(goal: Formula, actions: Iterable[ActionModel]) -> bool:
    """Whether a knowledge modality occurs in the goal or in any action's formulas.

    Examples
    --------
    >>> from epistemica.del_ import parse_formula, public_announcement
    >>> uses_knowledge(parse_formula("B[a] p"), [public_announcement("K[a] p", ["a"])])
    True
    >>> uses_knowledge(parse_formula("B[a] p"), [public_announcement("p", ["a"])])
    False
    """
    return any(
        isinstance(g, _KNOWLEDGE_NODES) for f in _formulas(goal, actions) for g in f.subformulas()
    )


def uses_distributed(goal: Formula, actions: Iterable[ActionModel]) -> bool:
    """Whether distributed knowledge ``D[G]`` occurs in the goal or in any action's
    formulas. Its truth is not invariant under bisimulation (it reads the intersection of
    relations, which a contraction can enlarge), so such a task is planned on states that
    are not contracted.

    Examples
    --------
    >>> from epistemica.del_ import parse_formula, public_announcement
    >>> uses_distributed(parse_formula("D[a, b] p"), [])
    True
    >>> uses_distributed(parse_formula("K[a] p"), [public_announcement("p", ["a"])])
    False
    """
    return any(
        isinstance(g, Distributed) for f in _formulas(goal, actions) for g in f.subformulas()
    )


def _formulas(goal: Formula, actions: Iterable[ActionModel]) -> list[Formula]:
    """The goal and every formula of the actions: preconditions, effects, edge conditions."""
    formulas = [goal]
    for action in actions:
        formulas.extend(action.pre)
        formulas.extend(v for changes in action.post for v in changes.values())
        for edges in (*action.edges.values(), *action.knowledge_edges.values()):
            formulas.extend(c for _, _, c in edges if c is not None)
    return formulas


def relevant_atoms(goal: Formula | str, actions: Iterable[ActionModel]) -> frozenset[str]:
    """The atoms that the goal or an action reads or assigns: all that planning can see.

    Examples
    --------
    >>> from epistemica.del_ import public_assignment
    >>> sorted(relevant_atoms("K[a] p", [public_assignment({"q": "r"}, ["a"])]))
    ['p', 'q', 'r']
    """
    actions = list(actions)
    found = {g.key for f in _formulas(as_formula(goal), actions) for g in f.atoms()}
    found.update(atom for action in actions for changes in action.post for atom in changes)
    return frozenset(found)


def relevant_agents(goal: Formula | str, actions: Iterable[ActionModel]) -> frozenset[str]:
    """The agents that a modality of the goal or of an action names.

    Examples
    --------
    >>> from epistemica.del_ import public_announcement
    >>> sorted(relevant_agents("K[a] p", [public_announcement("B[b] q", ["a", "b", "c"])]))
    ['a', 'b']
    """
    return frozenset(g for f in _formulas(as_formula(goal), actions) for g in f.agents())


def relevant_part(
    state: KripkeModel,
    actions: Mapping[str, ActionModel],
    goal: Formula | str,
    agents: Iterable[str] = (),
) -> tuple[KripkeModel, dict[str, ActionModel]]:
    """The state and actions without the atoms and agents no formula of them reads.

    An agent that no modality names changes no truth value, but its relation still
    splits states (and each action carries it); an unread atom doubles the worlds. The
    search, :func:`validate` and implicit coordination (which also keeps ``agents``, the
    owners whose perspectives it takes) all plan on this part, so they see the same
    states. Every formula over the kept atoms and agents keeps its truth (the state is
    contracted unless ``D[G]`` occurs: see :func:`uses_distributed`).

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel, public_announcement
    >>> s = KripkeModel.from_observables(["p", "junk"], {"a": [], "b": []}, designated=["p"])
    >>> small, acts = relevant_part(s, {"tell": public_announcement("p", ["a", "b"])}, "K[a] p")
    >>> small.atoms, small.agents, small.n_worlds
    (('p',), ('a',), 2)
    """
    goal = as_formula(goal)
    actions = dict(actions)
    named = relevant_agents(goal, actions.values()) | set(agents)
    keep = named & set(state.agents) or set(state.agents[:1])
    if len(keep) < len(state.agents):
        agents = tuple(a for a in state.agents if a in keep)
        state = _with_agents(state, agents)
        actions = {name: action_with_agents(a, agents) for name, a in actions.items()}
    contract = not uses_distributed(goal, actions.values())
    return project(state, relevant_atoms(goal, actions.values()), contract), actions


def _with_agents(state: KripkeModel, agents: tuple[str, ...]) -> KripkeModel:
    if state.cube is not None:
        return KripkeModel.from_cube(state.cube, state.atoms, agents, state.designated_codes)
    rel = {a: state.belief_relations[a] for a in agents}
    know = {a: state.knowledge_relations[a] for a in agents}
    return KripkeModel.from_arrays(
        state.lazy_names,
        state.atoms,
        state.valuation,
        agents,
        rel,
        know,
        state.designated_positions,
    )


def action_with_agents(action: ActionModel, agents: tuple[str, ...]) -> ActionModel:
    """The action model with the relations of ``agents`` only."""
    events = action.events

    def edges(table: dict, agent: str) -> list[tuple]:
        return [(events[e], events[f]) + (() if c is None else (c,)) for e, f, c in table[agent]]

    return ActionModel(
        events,
        dict(zip(events, action.pre, strict=True)),
        dict(zip(events, action.post, strict=True)),
        {a: edges(action.edges, a) for a in agents},
        list(action.designated),
        knowledge={a: edges(action.knowledge_edges, a) for a in agents},
    )


def project(state: KripkeModel, atoms: Iterable[str], contract: bool = True) -> KripkeModel:
    """The state on ``atoms`` only, contracted: formulas over them keep their truth
    (with ``contract=False``, the generated submodel on ``atoms``: formulas with ``D[G]``
    keep theirs too).

    Planning never reads an atom that no action or goal mentions, but such an atom may
    multiply the worlds (each unknown one doubles them); projecting it away first keeps
    the search the size of the relevant part.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "junk"], {"a": ["p"]}, designated=["p"])
    >>> small = project(m, ["p"])
    >>> small.n_worlds, small.atoms, small.holds("K[a] p")
    (2, ('p',), True)
    """
    keep = set(atoms)
    columns = [j for j, a in enumerate(state.atoms) if a in keep]
    if len(columns) == len(state.atoms):
        return state
    if state.cube is not None and contract:
        found = _project_cube(state, columns)
        if found is not None:
            return found
    projected = KripkeModel.from_arrays(
        state.lazy_names,
        tuple(state.atoms[j] for j in columns),
        state.valuation[:, columns],
        state.agents,
        state.belief_relations,
        state.knowledge_relations,
        state.designated_positions,
    )
    return projected.minimize() if contract else generated_submodel(projected)


def _project_cube(state: KripkeModel, columns: list[int]) -> KripkeModel | None:
    """Projection of a model from observables whose worlds are a product over the
    dropped atoms (every value of them goes with every live valuation of the others):
    the model from observables of the kept atoms, then, is bisimilar to the state.
    ``None`` when the worlds are not such a product (a law ties the dropped atoms)."""
    cube = state.cube
    n = cube.n_bits
    dropped = [n - 1 - j for j in range(n) if j not in set(columns)]
    any_dropped = cube.zeros()
    for p in dropped:
        if not cube.closed_under_flip(p):
            return None
        any_dropped |= cube.atom(n - 1 - p)
    kept = [n - 1 - j for j in columns]  # code bit positions, most significant first
    codes = cube.restrict(~any_dropped).codes
    new_codes = _compress(codes, kept)
    points = np.unique(_compress(np.asarray(state.designated_codes), kept))
    position = {p: len(kept) - 1 - i for i, p in enumerate(kept)}
    hidden = {a: tuple(position[p] for p in cube.hidden[a] if p in position) for a in state.agents}
    small = Cube.full(len(kept), hidden)
    flags = np.zeros(small.space.words * 64, dtype=bool)
    flags[new_codes] = True
    small = Cube(small.space, pack_bits(flags))
    atoms = tuple(state.atoms[j] for j in columns)
    return KripkeModel.from_cube(small, atoms, state.agents, points.astype(np.intp))


def _compress(codes: np.ndarray, kept: list[int]) -> np.ndarray:
    """Codes with only the bits at positions ``kept`` (most significant first), packed."""
    out = np.zeros(len(codes), dtype=np.intp)
    for i, p in enumerate(kept):
        out |= ((codes >> p) & 1) << (len(kept) - 1 - i)
    return out


def forget_knowledge(state: KripkeModel) -> KripkeModel:
    """The same state with each agent's knowledge relation replaced by its belief relation."""
    if not state.has_separate_knowledge():
        return state
    rel = state.belief_relations
    return KripkeModel.from_arrays(
        state.lazy_names,
        state.atoms,
        state.valuation,
        state.agents,
        rel,
        dict(rel),
        state.designated_positions,
    )
