"""Atoms that no action or goal mentions do not change plans (and are projected away)."""

from __future__ import annotations

from pathlib import Path

import pytest

from epistemica.del_ import KripkeModel, load_spec, plan, validate
from epistemica.del_.planning.planner import project, relevant_agents, relevant_atoms

SPECS = Path(__file__).resolve().parents[2] / "specs" / "planning"


def _with_irrelevant_atoms(path: Path, k: int, folder: Path, agents: int = 0) -> Path:
    lines = path.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("atoms "))
    lines.insert(at + 1, "atoms " + ", ".join(f"irrelevant{j}" for j in range(k)))
    if agents:
        at = next(i for i, line in enumerate(lines) if line.startswith("agents "))
        lines[at] += ", " + ", ".join(f"bystander{j}" for j in range(agents))
    out = folder / path.name
    out.write_text("\n".join(lines) + "\n")
    return out


@pytest.mark.parametrize("name", ["sally_anne", "coin_in_the_box_a", "selective_communication"])
def test_same_plan_with_ten_irrelevant_atoms(name, tmp_path):
    spec = load_spec(SPECS / f"{name}.epi")
    padded = load_spec(_with_irrelevant_atoms(SPECS / f"{name}.epi", 10, tmp_path))
    assert padded.model.n_worlds == spec.model.n_worlds * 2**10  # nobody observes them
    expected = plan(spec.model, spec.actions, spec.goal)
    assert expected is not None
    assert plan(padded.model, padded.actions, padded.goal) == expected


@pytest.mark.parametrize("name", ["sally_anne", "coin_in_the_box_a"])
def test_same_plan_with_irrelevant_agents(name, tmp_path):
    spec = load_spec(SPECS / f"{name}.epi")
    padded = load_spec(_with_irrelevant_atoms(SPECS / f"{name}.epi", 2, tmp_path, agents=2))
    assert len(padded.agents) == len(spec.agents) + 2
    expected = plan(spec.model, spec.actions, spec.goal)
    assert plan(padded.model, padded.actions, padded.goal) == expected
    # the bystanders are left out of the search, not out of the problem
    assert relevant_agents(padded.goal, padded.actions.values()) <= set(spec.agents)


def test_relevant_atoms_are_those_read_or_assigned():
    spec = load_spec(SPECS / "sally_anne.epi")
    found = relevant_atoms(spec.goal, spec.actions.values())
    assert found <= set(spec.model.atoms)
    assert {a.key for a in spec.goal.atoms()} <= found


def test_projection_of_a_product_forgets_the_atom():
    """j is independent of p: dropping it leaves 'a sees nothing about p'."""
    m = KripkeModel.from_observables(["p", "j"], {"a": ["j"], "b": ["p"]}, designated=["p"])
    small = project(m, ["p"])
    assert small.atoms == ("p",) and small.n_worlds == 2
    assert small.holds("p & ~Kw[a] p & K[b] p & K[a] Kw[b] p")


def test_projection_keeps_what_a_law_ties_to_the_dropped_atom():
    """With the law p <-> j, a sees j and so knows p: still true without j."""
    observes = {"a": ["j"], "b": []}
    m = KripkeModel.from_observables(["p", "j"], observes, law="p <-> j", designated=["p", "j"])
    assert m.holds("K[a] p & ~Kw[b] p")
    small = project(m, ["p"])
    assert small.atoms == ("p",) and small.n_worlds == 2
    assert small.holds("K[a] p & ~Kw[b] p & K[b] Kw[a] p")


def test_validation_sees_the_states_the_search_sees(tmp_path):
    """validate projects as the search does: with 8 atoms nobody observes added to
    grapevine (16,384 worlds), the validated states have the worlds of the plain spec."""
    spec = load_spec(SPECS / "grapevine.epi")
    padded = load_spec(_with_irrelevant_atoms(SPECS / "grapevine.epi", 8, tmp_path))
    assert padded.model.n_worlds == 2**14
    steps = plan(spec.model, spec.actions, spec.goal)
    assert plan(padded.model, padded.actions, padded.goal) == steps
    plain = validate(spec.model, spec.actions, steps, spec.goal)
    run = validate(padded.model, padded.actions, steps, padded.goal)
    assert plain and run
    assert [s.n_worlds for s in run.states] == [s.n_worlds for s in plain.states]
    assert all(not any(a.startswith("irrelevant") for a in s.atoms) for s in run.states)
    # and a wrong plan is still refused, at the same step
    wrong = ["share_b_b", *steps]
    assert validate(padded.model, padded.actions, wrong, padded.goal).step == (
        validate(spec.model, spec.actions, wrong, spec.goal).step
    )


def test_implicit_coordination_keeps_owners_and_drops_the_rest(tmp_path):
    from epistemica.del_ import check_implicit_coordination, plan_implicitly_coordinated

    path = SPECS / "two_robots_implicit.epi"
    spec = load_spec(path)
    padded = load_spec(_with_irrelevant_atoms(path, 6, tmp_path, agents=2))
    found = plan_implicitly_coordinated(spec.model, spec.actions, spec.owners, spec.goal)
    assert found == ["go_r1_g1", "go_r2_g2"]
    assert (
        plan_implicitly_coordinated(padded.model, padded.actions, padded.owners, padded.goal)
        == found
    )
    # the owners are named by no formula (the goal and preconditions are propositional),
    # yet their perspectives are what makes the other order fail
    report = check_implicit_coordination(
        padded.model, padded.actions, padded.owners, ["go_r2_g2", "go_r1_g1"], padded.goal
    )
    assert not report and (report.step, report.agent) == (1, "r1")
