"""Implicitly coordinated policies: hand-worked examples and the laws a policy obeys.

The door-mat example is the running example of Engesser, Bolander, Mattmüller and Nebel
(2017) (its facts: Anne knows whether the key is under the mat, Bob does not and has no
key; Bob's try-take gets the key if it is there and he sees whether it did; Anne can
announce that it is there). The expected verdicts below are worked out by hand from the
definitions, world by world, as in the comments.

The properties are checked by an executor written here from the definition of an
execution (the actual world moves on; the acting agent picks its decision from what it
knows), independent of :func:`check_policy`'s reasoning over perspectives.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import Top, check_implicit_coordination, load_spec, parse_formula
from epistemica.del_.planning.coordination import perspective, pointed_at
from epistemica.del_.planning.planner import applicable_in_all
from epistemica.del_.planning.policy import (
    Decision,
    Policy,
    check_policy,
    plan_policy,
)

SPECS = Path(__file__).resolve().parents[2] / "specs" / "planning"


def spec(name):
    found = SPECS / f"{name}.epi"
    return load_spec(found if found.exists() else SPECS / "policies" / f"{name}.epi")


def chain(owners, *steps):
    """A policy without branches: each step's owner does it, whatever it knows."""
    decisions: tuple = ()
    for name in reversed(steps):
        decisions = (Decision(owners[name], Top(), name, decisions),)
    return Policy(decisions)


# -- the door mat (Engesser et al. 2017) ------------------------------------------------


def test_door_mat_try_take_alone_reaches_the_goal_but_not_implicitly():
    s = spec("door_mat")
    # Bob's perspective holds the world without the key under the mat, where his try
    # takes nothing: he does not know the plan works.
    report = check_implicit_coordination(s.model, s.actions, s.owners, ["try_take"], s.goal)
    assert not report and report.agent == "bob" and report.kind == "goal"
    assert not check_policy(s.model, s.actions, s.owners, s.goal, chain(s.owners, "try_take"))
    # Were Anne to try, she knows the key is there: implicitly coordinated.
    anne_owns = {**s.owners, "try_take": "anne"}
    assert check_implicit_coordination(s.model, s.actions, anne_owns, ["try_take"], s.goal)
    assert check_policy(s.model, s.actions, anne_owns, s.goal, chain(anne_owns, "try_take"))


def test_door_mat_announce_then_take_is_the_least_policy():
    s = spec("door_mat")
    found = plan_policy(s.model, s.actions, s.owners, s.goal)
    # After Anne's public announcement Bob knows the key is there: depth 2, no branch.
    assert found.policy == chain(s.owners, "announce", "try_take")
    assert found.policy.depth == 2 and found.complete
    assert check_policy(s.model, s.actions, s.owners, s.goal, found.policy)


def test_door_mat_has_no_policy_from_bobs_perspective():
    s = spec("door_mat")
    # Bob considers a world without the key: there nobody can get it to him.
    found = plan_policy(s.model, s.actions, s.owners, s.goal, perspective_of="bob")
    assert found.policy is None and found.complete
    # Anne knows the key is there: her perspective is the actual world's.
    from_anne = plan_policy(s.model, s.actions, s.owners, s.goal, perspective_of="anne")
    assert from_anne.policy == chain(s.owners, "announce", "try_take")


# -- the two robots ----------------------------------------------------------------------


def test_two_robots_policy_branches_on_r1s_knowledge_from_r2s_perspective():
    s = spec("two_robots_implicit")
    # From the actual world (r1's task is g1) the policy is the sequential plan.
    plain = plan_policy(s.model, s.actions, s.owners, s.goal).policy
    assert plain == chain(s.owners, "go_r1_g1", "go_r2_g2")
    # r2 cannot tell where r1's task is: r1 moves to its task, r2 to the other spot.
    found = plan_policy(s.model, s.actions, s.owners, s.goal, perspective_of="r2").policy
    target = parse_formula("target1")
    expected = Policy(
        (
            Decision("r1", target, "go_r1_g1", (Decision("r2", Top(), "go_r2_g2"),)),
            Decision(
                "r1", parse_formula("~target1"), "go_r1_g2", (Decision("r2", Top(), "go_r2_g1"),)
            ),
        )
    )
    assert found == expected
    assert check_policy(s.model, s.actions, s.owners, s.goal, found, perspective_of="r2")


def test_policy_checks_fail_where_the_definition_says():
    s = spec("two_robots_implicit")
    check = lambda policy: check_policy(  # noqa: E731
        s.model, s.actions, s.owners, s.goal, policy, perspective_of="r2"
    )
    # r2 first: it does not know which spot r1 needs
    wrong_order = chain(s.owners, "go_r2_g2", "go_r1_g1")
    assert not check(wrong_order)
    # no branch: r1 cannot go to g1 in the world where its task is g2
    assert (
        "does not know that go_r1_g1 is applicable"
        in check(chain(s.owners, "go_r1_g1", "go_r2_g2")).reason
    )
    # a condition r1 cannot evaluate to a single decision
    both = Policy(
        (
            Decision("r1", Top(), "go_r1_g1", (Decision("r2", Top(), "go_r2_g2"),)),
            Decision("r1", Top(), "go_r1_g2", (Decision("r2", Top(), "go_r2_g1"),)),
        )
    )
    assert "cannot tell which decision" in check(both).reason
    # r2 may not do r1's action
    stolen = Policy((Decision("r2", Top(), "go_r1_g1"),))
    assert "its owner is r1" in check(stolen).reason


# -- the harder domains -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "first", "depth", "branches"),
    [("tiger_signal", ("l", "listen"), 3, 2), ("corridor_relay", ("s", "look"), 4, 2)],
)
def test_harder_domains_need_a_branching_policy(name, first, depth, branches):
    s = spec(name)
    from epistemica.del_ import plan_implicitly_coordinated

    # every valuation is designated: no sequence works whichever world is actual
    assert plan_implicitly_coordinated(s.model, s.actions, s.owners, s.goal) is None
    found = plan_policy(s.model, s.actions, s.owners, s.goal)
    policy = found.policy
    assert policy.depth == depth
    (root,) = policy.decisions
    assert (root.agent, root.action) == first
    assert len(root.then) == branches  # what the first agent sensed decides
    assert check_policy(s.model, s.actions, s.owners, s.goal, policy)
    assert strong_by_execution(s, policy)


def test_tiger_signal_policy_by_hand():
    s = spec("tiger_signal")
    found = plan_policy(s.model, s.actions, s.owners, s.goal).policy
    left, right = parse_formula("tiger_left"), parse_formula("~tiger_left")
    assert found == Policy(
        (
            Decision(
                "l",
                Top(),
                "listen",
                (
                    Decision("l", left, "go_right", (Decision("o", Top(), "open_right"),)),
                    Decision("l", right, "go_left", (Decision("o", Top(), "open_left"),)),
                ),
            ),
        )
    )


# -- properties: found policies are strong, from every acting agent's perspective ------


def strong_by_execution(s, policy, root=None) -> bool:
    """Run the policy from every designated world (and, at each decision, from every
    world the acting agent considers possible): every run must end where the goal
    holds, with each step applicable in the acting agent's whole local state."""
    from epistemica.del_.explicit.bisimulation import generated_submodel

    state = generated_submodel(s.model if root is None else root)
    for point in state.designated_positions.tolist():
        if not run(s, pointed_at(state, [point]), policy.decisions, depth=0):
            return False
    return True


def run(s, world_state, decisions, depth) -> bool:
    if world_state.holds(s.goal, actions=s.actions):
        return True
    if not decisions or depth > 20:
        return False
    agent = decisions[0].agent
    local = perspective(world_state, agent)
    chosen = [d for d in decisions if local.holds(d.when)]
    if len(chosen) != 1:
        return False
    decision = chosen[0]
    action = s.actions[decision.action]
    if not applicable_in_all(local, action):
        return False
    # the agent's view: it must work from every world it considers possible
    outcome = local.update(action)
    return all(
        run(s, pointed_at(outcome, [p]), decision.then, depth + 1)
        for p in outcome.designated_positions.tolist()
    )


@settings(max_examples=25, deadline=None)
@given(
    st.sampled_from(["two_robots_implicit", "tiger_signal", "corridor_relay", "door_mat"]),
    st.data(),
)
def test_found_policies_are_strong_from_any_designated_worlds(name, data):
    """Designate a random nonempty set of worlds of the initial state: whenever a policy
    is found, every execution from every designated world reaches the goal, with every
    acting agent knowing its step is applicable; when none is found the search says
    whether that is proven."""
    s = spec(name)
    n = s.model.n_worlds
    chosen = data.draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=n, unique=True))
    initial = pointed_at(s.model, chosen)
    found = plan_policy(initial, s.actions, s.owners, s.goal, max_depth=6)
    if found.policy is None:
        return
    assert check_policy(initial, s.actions, s.owners, s.goal, found.policy)
    assert strong_by_execution(s, found.policy, root=initial)


def test_policy_round_trips_through_json():
    s = spec("corridor_relay")
    policy = plan_policy(s.model, s.actions, s.owners, s.goal).policy
    assert Policy.from_dict(policy.to_dict()) == policy
    assert "s, when it knows open_a: gate_a" in str(policy)


def test_unknown_names_in_a_policy_are_reported():
    s = spec("door_mat")
    bad = Policy((Decision("carol", Top(), "announce"),))
    assert "unknown agent" in check_policy(s.model, s.actions, s.owners, s.goal, bad).reason
    bad = Policy((Decision("anne", Top(), "shout"),))
    assert "unknown action" in check_policy(s.model, s.actions, s.owners, s.goal, bad).reason
