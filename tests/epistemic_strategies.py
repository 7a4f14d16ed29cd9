"""Hypothesis strategies for random formulas and Kripke models, and a naive reference checker.

The reference checker evaluates formulas straight from the textbook definitions over
explicit sets of pairs, world by world. It shares no code with epistemica's vectorised
checker, so agreement between the two is evidence that both follow the definitions.
"""

from __future__ import annotations

import itertools

from hypothesis import strategies as st

from epistemica.del_ import (
    After,
    And,
    Announce,
    AnnounceDiamond,
    Atom,
    Believe,
    Bottom,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Iff,
    Implies,
    Know,
    KnowWhether,
    KripkeModel,
    Not,
    Or,
    Top,
)

AGENTS = ("a", "b")
ATOMS = ("p", "q", "r")


def formulas(atoms=ATOMS, agents=AGENTS, max_leaves=12, announcements=True, actions=None):
    """Random formulas over every node kind of the logic.

    ``atoms`` and ``agents`` are names to sample from, or strategies (of ``Atom`` nodes and
    of agent names) for wider alphabets such as the parser's; a drawn group has 1 to 3
    agents (repeats collapse). ``announcements`` adds ``[!f] g`` and ``<!f> g``; ``actions``
    (names, or a strategy of names) adds ``[ACT] g``, left out by default because it needs
    action models to evaluate.
    """
    if isinstance(agents, st.SearchStrategy):
        agent = agents
        groups = st.lists(agents, min_size=1, max_size=3)
    else:
        agent = st.sampled_from(agents)
        groups = st.lists(agent, min_size=1, max_size=len(agents), unique=True)
    if not isinstance(atoms, st.SearchStrategy):
        atoms = st.sampled_from([Atom(a) for a in atoms])
    leaves = st.one_of(atoms, st.just(Top()), st.just(Bottom()))

    def extend(children):
        options = [
            children.map(Not),
            st.builds(And, children, children),
            st.builds(Or, children, children),
            st.builds(Implies, children, children),
            st.builds(Iff, children, children),
            st.builds(Know, agent, children),
            st.builds(Believe, agent, children),
            st.builds(KnowWhether, agent, children),
            st.builds(Everybody, groups, children),
            st.builds(Common, groups, children),
            st.builds(Distributed, groups, children),
            st.builds(EverybodyBelieves, groups, children),
            st.builds(CommonBelief, groups, children),
        ]
        if announcements:
            options += [
                st.builds(Announce, children, children),
                st.builds(AnnounceDiamond, children, children),
            ]
        if actions is not None:
            names = actions if isinstance(actions, st.SearchStrategy) else st.sampled_from(actions)
            options.append(st.builds(After, names, children))
        return st.one_of(options)

    return st.recursive(leaves, extend, max_leaves=max_leaves)


@st.composite
def partitions(draw, n):
    """A random equivalence relation on range(n), as a list of pairs."""
    labels = draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))
    return [(w, v) for w in range(n) for v in range(n) if labels[w] == labels[v]]


@st.composite
def kd45_relations(draw, n):
    """A random serial, transitive, Euclidean relation on range(n).

    Worlds fall into components; each component has a nonempty set of believed worlds,
    and every world of the component points to exactly those.
    """
    component = draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))
    pairs = []
    for c in set(component):
        members = [w for w in range(n) if component[w] == c]
        believed = draw(st.lists(st.sampled_from(members), min_size=1, unique=True))
        pairs += [(w, v) for w in members for v in believed]
    return pairs


@st.composite
def arbitrary_relations(draw, n):
    """Any relation on range(n), seriality not guaranteed."""
    return draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=3 * n))


@st.composite
def kd45_in_s5(draw, n):
    """(belief, knowledge): an S5 knowledge relation and a KD45 belief relation inside it.

    Each knowledge class has a nonempty set of believed worlds, which every world of the
    class points to (so belief may be false while knowledge is truthful).
    """
    labels = draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))
    belief, knowledge = [], []
    for c in set(labels):
        members = [w for w in range(n) if labels[w] == c]
        believed = draw(st.lists(st.sampled_from(members), min_size=1, unique=True))
        belief += [(w, v) for w in members for v in believed]
        knowledge += [(w, v) for w in members for v in members]
    return belief, knowledge


@st.composite
def models(draw, kind="s5", max_worlds=6, atoms=ATOMS, agents=AGENTS):
    """A random Kripke model of the given kind.

    ``"s5"``, ``"kd45"`` or ``"any"``: one relation per agent of that class (belief and
    knowledge coincide); ``"kd45-s5"``: separate KD45 belief inside S5 knowledge.
    """
    n = draw(st.integers(1, max_worlds))
    valuation = {
        w: draw(st.lists(st.sampled_from(atoms), unique=True, max_size=len(atoms)))
        for w in range(n)
    }
    knowledge = None
    if kind == "kd45-s5":
        pairs = {a: draw(kd45_in_s5(n)) for a in agents}
        relations = {a: belief for a, (belief, _) in pairs.items()}
        knowledge = {a: know for a, (_, know) in pairs.items()}
    else:
        relation = {"s5": partitions, "kd45": kd45_relations, "any": arbitrary_relations}[kind]
        relations = {a: draw(relation(n)) for a in agents}
    designated = draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=2, unique=True))
    return KripkeModel(
        list(range(n)), valuation, relations, designated, knowledge=knowledge, atoms=atoms
    )


def explicit_copy(model):
    """The same model rebuilt from its worlds and pairs (no bitset cube), same vocabulary."""
    worlds = list(model.worlds)
    return KripkeModel(
        worlds,
        {w: model.valuation_of(w) for w in worlds},
        {a: [(w, v) for w in worlds for v in model.successors(a, w)] for a in model.agents},
        list(model.designated),
        atoms=model.atoms,
    )


# -- the reference checker -------------------------------------------------------------


def explicit(model):
    """(worlds, valuation, relations) of a model as plain Python sets."""
    worlds = list(model.worlds)
    valuation = {w: model.valuation_of(w) for w in worlds}
    belief = {a: {(w, v) for w in worlds for v in model.successors(a, w)} for a in model.agents}
    know = {
        a: {(w, v) for w in worlds for v in model.successors(a, w, relation="knowledge")}
        for a in model.agents
    }
    return worlds, valuation, belief, know


def reference_truth(model, formula):
    """The set of worlds where ``formula`` holds, by direct recursion on the definitions."""
    worlds, valuation, belief, know = explicit(model)
    return _truth(formula, frozenset(worlds), valuation, belief, know)


def _succ(relation, w, worlds):
    return {v for (x, v) in relation if x == w and v in worlds}


def _truth(f, worlds, val, belief, know):
    rec = lambda g, ws=worlds: _truth(g, ws, val, belief, know)  # noqa: E731
    if isinstance(f, Atom):
        return {w for w in worlds if f.key in val[w]}
    if isinstance(f, Top):
        return set(worlds)
    if isinstance(f, Bottom):
        return set()
    if isinstance(f, Not):
        return set(worlds) - rec(f.operand)
    if isinstance(f, And):
        return rec(f.left) & rec(f.right)
    if isinstance(f, Or):
        return rec(f.left) | rec(f.right)
    if isinstance(f, Implies):
        return (set(worlds) - rec(f.left)) | rec(f.right)
    if isinstance(f, Iff):
        left, right = rec(f.left), rec(f.right)
        return {w for w in worlds if (w in left) == (w in right)}
    if isinstance(f, (Know, Believe)):
        rel = know[f.agent] if isinstance(f, Know) else belief[f.agent]
        inner = rec(f.operand)
        return {w for w in worlds if _succ(rel, w, worlds) <= inner}
    if isinstance(f, KnowWhether):
        return rec(Or(Know(f.agent, f.operand), Know(f.agent, Not(f.operand))))
    if isinstance(f, (Everybody, EverybodyBelieves)):
        rel = know if isinstance(f, Everybody) else belief
        inner = rec(f.operand)
        return {w for w in worlds if all(_succ(rel[a], w, worlds) <= inner for a in f.group)}
    if isinstance(f, (Common, CommonBelief)):
        rel = know if isinstance(f, Common) else belief
        inner = rec(f.operand)
        out = set()
        for w in worlds:
            frontier, seen = {w}, set()
            while frontier:  # worlds reachable in >= 1 step
                step = set().union(*(_succ(rel[a], x, worlds) for a in f.group for x in frontier))
                frontier = step - seen
                seen |= step
            if seen <= inner:
                out.add(w)
        return out
    if isinstance(f, Distributed):
        inner = rec(f.operand)
        out = set()
        for w in worlds:
            common = set.intersection(*(_succ(know[a], w, worlds) for a in f.group))
            if common <= inner:
                out.add(w)
        return out
    if isinstance(f, (Announce, AnnounceDiamond)):
        announced = rec(f.announcement)
        after = rec(f.operand, frozenset(announced))
        if isinstance(f, Announce):
            return (set(worlds) - announced) | after
        return after
    if isinstance(f, After):
        raise NotImplementedError("the reference checker does not run actions")
    raise TypeError(f)


def all_subsets(items):
    """Every subset of ``items``, smallest first."""
    items = list(items)
    return itertools.chain.from_iterable(
        itertools.combinations(items, k) for k in range(len(items) + 1)
    )
