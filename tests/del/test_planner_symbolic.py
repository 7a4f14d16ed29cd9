"""Planning over knowledge structures: the same plans as the explicit planner, normal
forms bisimilar to what they normalise, keys that never merge different states."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import (
    KnowledgeStructure,
    bisimilar,
    load_spec,
    plan_with_stats,
    public_announcement,
    public_assignment,
    semi_private_sensing,
)
from epistemica.del_ import load_spec as load_with_backend
from epistemica.del_.explicit.action import private_announcement
from epistemica.del_.planning.symbolic_search import (
    applicable_in_all_symbolic,
    choose_backend,
    plan_symbolic_with_stats,
    relevant_structure,
    validate_symbolic,
)
from epistemica.del_.symbolic.normal_form import normalise, state_key, without_free_atoms

ROOT = Path(__file__).resolve().parents[2]
SPECS = ROOT / "specs" / "planning"
sys.path.insert(0, str(ROOT / "benchmarks"))
from scaled_planning import collaboration, selective_communication  # noqa: E402

# Small specs covering every kind of action the benchmarks use: public and private
# sensing, mA* executability, oblivious agents, belief collapse, ontic change.
SHIPPED = [
    "sally_anne",
    "coin_in_the_box_a",
    "coin_in_the_box_b",
    "selective_communication",
    "cc_2_2_3_pl3",
    "assembly_line_02",
    "two_robots_implicit",
]


@pytest.mark.parametrize("name", SHIPPED)
def test_same_shortest_plans_as_the_explicit_planner(name):
    explicit = load_spec(SPECS / f"{name}.epi")
    symbolic = load_with_backend(SPECS / f"{name}.epi", "symbolic")
    expected = plan_with_stats(explicit.model, explicit.actions, explicit.goal, max_depth=8)
    found = plan_symbolic_with_stats(symbolic.model, symbolic.actions, symbolic.goal, max_depth=8)
    assert found.length == expected.length
    # the symbolic plan is valid for both backends
    assert validate_symbolic(symbolic.model, symbolic.actions, found.plan, symbolic.goal)
    from epistemica.del_ import validate

    assert validate(explicit.model, explicit.actions, found.plan, explicit.goal)


@pytest.mark.parametrize("search", ["astar", "greedy"])
def test_heuristic_searches_over_structures_return_valid_plans(search):
    spec = load_with_backend(SPECS / "coin_in_the_box_b.epi", "symbolic")
    found = plan_symbolic_with_stats(spec.model, spec.actions, spec.goal, search=search)
    assert found.plan is not None and found.search == search
    assert validate_symbolic(spec.model, spec.actions, found.plan, spec.goal)
    blind = plan_symbolic_with_stats(
        spec.model, spec.actions, spec.goal, search="astar", heuristic="blind"
    )
    assert blind.length == 4  # blind A* is admissible: the shortest length, as BFS


def test_no_plan_is_reported_complete_when_the_space_is_exhausted():
    spec = load_with_backend(SPECS / "sally_anne.epi", "symbolic")
    # K instead of B: knowledge is truthful, so no plan exists (docs/planning.md)
    goal = str(spec.goal).replace("B[", "K[")
    result = plan_symbolic_with_stats(spec.model, spec.actions, goal)
    assert result.plan is None and result.complete


def _structures_after(actions):
    """Every prefix of a random run, as (structure, Kripke model) pairs."""
    s = KnowledgeStructure.from_observables(
        ["p", "q", "r"], {"a": ["p"], "b": ["q"]}, law="p | q | r", designated=["p", "r"]
    )
    m = s.to_kripke()
    out = [(s, m)]
    for action in actions:
        if not s.applicable_in_some(action):
            break
        s, m = s.update(action), m.update(action)
        out.append((s, m))
    return out


ACTIONS = [
    public_announcement("p | q", ["a", "b"]),
    public_announcement("K[a] p | ~r", ["a", "b"]),
    semi_private_sensing("r", ["a"], ["a", "b"]),
    semi_private_sensing("p", ["b"], ["a", "b"]),
    private_announcement("q", ["b"], ["a", "b"]),
    public_assignment({"r": "~r"}, ["a", "b"]),
    public_assignment({"p": "true", "q": "p & r"}, ["a", "b"]),
]
RUNS = st.lists(st.sampled_from(range(len(ACTIONS))), max_size=4)


@settings(max_examples=60, deadline=None)
@given(RUNS)
def test_normal_forms_are_bisimilar_to_the_structures(run):
    for structure, model in _structures_after([ACTIONS[i] for i in run]):
        normal = normalise(structure)
        assert bisimilar(normal.to_kripke(4096), model)
        assert normal.n_variables <= structure.n_variables


@settings(max_examples=40, deadline=None)
@given(RUNS, RUNS)
def test_equal_keys_mean_bisimilar_states(first, second):
    one = _structures_after([ACTIONS[i] for i in first])[-1]
    two = _structures_after([ACTIONS[i] for i in second])[-1]
    same_key = state_key(normalise(one[0])) == state_key(normalise(two[0]))
    if same_key:
        assert bisimilar(one[1], two[1])


@settings(max_examples=40, deadline=None)
@given(st.permutations(range(4)))
def test_commuting_public_steps_give_one_key(order):
    """Public assignments to different atoms, and semi-private sensing (S5 all along:
    the normal form keeps atoms only), in any order reach one key."""
    agents = ["a", "b"]
    steps = [
        public_assignment({"p": "true"}, agents),
        public_assignment({"q": "~q"}, agents),
        semi_private_sensing("r", ["a"], agents),
        public_announcement("s | ~s", agents),
    ]
    s = KnowledgeStructure.from_observables(["p", "q", "r", "s"], {"a": ["p"], "b": ["q"]})
    keys = set()
    for ordering in ([0, 1, 2, 3], list(order)):
        state = s
        for i in ordering:
            state = state.update(steps[i])
        normal = normalise(state)
        assert set(normal.slots) == set(normal.atom_slots.values())  # atoms only
        keys.add(state_key(normal))
    assert len(keys) == 1


def test_dropping_free_atoms_keeps_what_the_rest_says():
    s = KnowledgeStructure.from_observables(
        ["p", "q", "junk", "tied"],
        {"a": ["p", "junk"], "b": ["tied"]},
        law="tied <-> q",
        designated=["p", "q", "tied"],
    )
    small = without_free_atoms(s, ["p", "q"], ["a", "b"])
    assert "junk" not in small.atoms and "tied" in small.atoms  # the law ties it to q
    for formula in ("K[a] p", "K[b] q", "~Kw[a] q", "K[a] K[b] q | K[a] K[b] ~q", "M[b] ~p"):
        assert small.holds(formula) == s.holds(formula)


def test_relevant_structure_keeps_the_named_agents():
    s = KnowledgeStructure.from_observables(["p"], {"a": [], "b": ["p"], "c": []})
    small, actions = relevant_structure(
        s, {"t": public_announcement("p", ["a", "b", "c"])}, "K[b] p"
    )
    assert small.agents == ("b",) and actions["t"].agents == ("b",)


def test_applicability_needs_every_designated_state():
    s = KnowledgeStructure.from_observables(["p"], {"a": []})
    assert not applicable_in_all_symbolic(s, public_announcement("p", ["a"]))
    assert applicable_in_all_symbolic(s.announce("p"), public_announcement("p", ["a"]))


def test_the_budget_chooses_the_backend():
    from epistemica.del_.budget import budget_scope

    assert choose_backend(10, 2) == "explicit"
    assert choose_backend(40, 2) == "symbolic"  # 2^40 valuations
    with budget_scope(2**20):
        assert choose_backend(18, 2) == "symbolic"  # 2^18 worlds' arrays exceed 1 MiB


def test_scaled_selective_communication_beyond_the_explicit_backend(tmp_path):
    """30 rooms and 8 listeners: 31 atoms, which the explicit backend refuses to
    enumerate; the symbolic planner walks to room 2, senses, walks to the last
    listener and shouts (its shortest plan: the published 5 steps of the 4-room
    instance grow by one per room)."""
    path = tmp_path / "sc.epi"
    path.write_text(selective_communication(30, 8))
    spec = load_with_backend(path, "symbolic")
    assert choose_backend(len(spec.atoms), len(spec.agents)) == "symbolic"
    result = plan_symbolic_with_stats(spec.model, spec.actions, spec.goal)
    assert result.plan[:2] == ["right", "sense"] and result.plan[-1] == "shout"
    assert set(result.plan[2:-1]) == {"right"}
    assert validate_symbolic(spec.model, spec.actions, result.plan, spec.goal)


def test_scaled_instances_agree_with_the_explicit_planner_where_both_run(tmp_path):
    for name, text in [
        ("sc", selective_communication(6, 3)),
        ("cc", collaboration(2, 2, 3, "partial")),
        ("cc5", collaboration(2, 2, 5, "partial")),
    ]:
        path = tmp_path / f"{name}.epi"
        path.write_text(text)
        explicit = load_spec(path)
        symbolic = load_with_backend(path, "symbolic")
        want = plan_with_stats(explicit.model, explicit.actions, explicit.goal, max_depth=12)
        got = plan_symbolic_with_stats(symbolic.model, symbolic.actions, symbolic.goal)
        assert got.length == want.length
        # atom-only normal forms: the keys are exact, so the same states are found
        if name.startswith("cc"):
            assert got.distinct == want.distinct


def test_cli_chooses_the_symbolic_backend_above_the_budget(tmp_path):
    path = tmp_path / "sc.epi"
    path.write_text(selective_communication(30, 8))
    run = [sys.executable, "-m", "epistemica", "plan", str(path)]
    done = subprocess.run(run, capture_output=True, text=True, check=False)
    assert done.returncode == 0 and "symbolic, bfs" in done.stdout
    assert "validated: the plan reaches the goal in 29 step(s)" in done.stdout
    refused = subprocess.run(
        [*run, "--backend", "explicit"], capture_output=True, text=True, check=False
    )
    assert refused.returncode == 2 and "too many to enumerate" in refused.stderr
