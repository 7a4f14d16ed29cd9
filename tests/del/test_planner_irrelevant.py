"""Atoms that no action or goal mentions do not change plans (and are projected away)."""

from __future__ import annotations

from pathlib import Path

import pytest

from epistemica.del_ import KripkeModel, load_spec, plan
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
