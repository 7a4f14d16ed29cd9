"""The standard epistemic planning benchmarks (specs/planning): shortest plan lengths
found by breadth-first search against the published lengths of
shared/reference/planning-benchmarks.md, each plan validated."""

from __future__ import annotations

from pathlib import Path

import pytest

from epistemica.del_ import load_spec, plan, plan_with_stats, validate

SPECS = Path(__file__).resolve().parents[2] / "specs" / "planning"

# instance file -> published shortest plan length
PUBLISHED = {
    "coin_in_the_box_a.epi": 2,
    "coin_in_the_box_b.epi": 4,
    "coin_in_the_box_c.epi": 5,
    "selective_communication.epi": 5,
    "selective_communication_depth2.epi": 5,
    "grapevine.epi": 4,
    "cc_2_2_3_pl3.epi": 3,
    "cc_2_2_3_pl4.epi": 4,
    "cc_2_2_3_pl5.epi": 5,
    "cc_2_2_3_pl7.epi": 7,
    "cc_2_2_3_pl8.epi": 8,
    "sally_anne.epi": 3,
    **{f"assembly_line_{n:02d}.epi": 5 for n in range(2, 11)},
}


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_shortest_plan_has_the_published_length(name):
    spec = load_spec(SPECS / name)
    result = plan_with_stats(spec.model, spec.actions, spec.goal)
    assert result.length == PUBLISHED[name]
    assert validate(spec.model, spec.actions, result.plan, spec.goal)


@pytest.mark.xfail(strict=True, reason="our encoding gives 7, not 6: see docs/planning.md")
def test_coin_in_the_box_d_published_length():
    spec = load_spec(SPECS / "coin_in_the_box_d.epi")
    found = plan(spec.model, spec.actions, spec.goal, max_depth=6)
    assert found is not None and len(found) == 6


def test_sally_anne_needs_belief_not_knowledge():
    spec = load_spec(SPECS / "sally_anne.epi")
    known = spec.formula("box & sally_in & K[sally] basket & K[anne] K[sally] basket")
    result = plan_with_stats(spec.model, spec.actions, known)
    assert result.plan is None and result.complete  # knowledge is truthful: impossible


def test_assembly_line_would_collapse_without_executability():
    # With `B[a] qa` inside the announcement's events, b (who missed a's sensing) ends with
    # no belief world, so B[b] ... holds vacuously and assembling takes 3 steps, not 5.
    from epistemica.del_ import observability_action

    spec = load_spec(SPECS / "assembly_line_02.epi")
    agents = list(spec.agents)
    actions = dict(spec.actions)
    actions["tell_a"] = observability_action(agents, pre="B[a] qa", announces="qa", full=agents)
    actions["tell_b"] = observability_action(agents, pre="B[b] qb", announces="qb", full=agents)
    assert len(plan(spec.model, actions, spec.goal)) < 5


def test_grapevine_goal_is_met_with_consistent_beliefs():
    spec = load_spec(SPECS / "grapevine.epi")
    found = ["move_a", "share_b_b", "move_c", "share_c_b"]  # the plan of the reference
    final = validate(spec.model, spec.actions, found, spec.goal).states[-1]
    assert final.holds("~B[a] false & ~B[b] false")  # not satisfied vacuously
