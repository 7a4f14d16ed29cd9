"""Mission kinds as objects (sim/kinds/): the registry, and each kind's laws checked against
brute force over its own configurations."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim import KINDS, MissionKind, Scenario, kind_named
from epistemica.sim.kinds.goal import ALLOCATION, CAPACITY, RENDEZVOUS
from epistemica.sim.kinds.tasks import COLLABORATIVE, MULTITASK
from epistemica.sim.policies.levels import KIND_LEVELS, level_names, make_level, parameters_for

GOAL_KINDS = (RENDEZVOUS, ALLOCATION, CAPACITY)


def test_the_registry_holds_every_kind_once_under_its_own_name():
    assert list(KINDS) == ["rendezvous", "allocation", "capacity", "multitask", "collaborative"]
    for name, kind in KINDS.items():
        assert isinstance(kind, MissionKind) and kind.name == name == str(kind)
        assert kind_named(name) is kind and kind_named(kind) is kind


def test_an_unknown_kind_is_refused_with_the_list():
    with pytest.raises(InvalidArgumentError, match="unknown mission kind 'relay'") as caught:
        kind_named("relay")
    assert "rendezvous, allocation" in caught.value.hint


def test_every_kind_has_levels_and_studies_only_levels_it_has():
    for name, kind in KINDS.items():
        assert set(kind.study_levels) <= set(level_names(kind)) == set(KIND_LEVELS[name])
        for level in kind.study_levels:
            assert make_level(kind, level, parameters_for(kind)()) is not None
    # Each kind's levels are its own: the joint oracle is the rules' level with full
    # communication, the goal missions' a least-makespan team with the same full view.
    assert "rules" in level_names(COLLABORATIVE) and "rules" not in level_names(ALLOCATION)
    joint = make_level(COLLABORATIVE, "oracle", parameters_for(COLLABORATIVE)())
    goal = make_level(ALLOCATION, "oracle", parameters_for(ALLOCATION)())
    assert type(joint) is not type(goal) and joint.shares == goal.shares == "everything"


def test_task_kinds_have_no_configuration_set_and_say_why():
    for kind in (MULTITASK, COLLABORATIVE):
        assert kind.tasks and kind.count(3, 5) == 0
        with pytest.raises(InvalidArgumentError, match="no fixed configuration set") as caught:
            kind.configurations(3, 5)
        assert caught.value.hint


def test_a_scenario_refuses_a_joint_kind_and_names_the_kinds_it_holds():
    with pytest.raises(InvalidArgumentError, match="unknown mission 'collaborative'") as caught:
        Scenario("collaborative", [[0, 0]], [[5, 5]], ["range"])
    assert "collaborative" not in caught.value.hint and "multitask" in caught.value.hint


def _capacities(kind, m: int, n: int, rng: np.random.Generator):
    if not kind.capacities:
        return None
    return np.bincount(rng.integers(0, m, size=n), minlength=m).tolist()


@settings(max_examples=60, deadline=None)
@given(
    st.sampled_from(GOAL_KINDS),
    st.integers(1, 4),
    st.integers(1, 4),
    st.integers(0, 2**32 - 1),
)
def test_cheapest_is_the_least_total_cost_of_the_kinds_configurations(kind, n, m, seed):
    rng = np.random.default_rng(seed)
    if kind.distinct and m < n:
        m = n
    caps = _capacities(kind, m, n, rng)
    cost = rng.uniform(0, 10, size=(n, m))
    row = kind.cheapest(cost, np.arange(m), caps)
    rows = kind.configurations(n, m, caps)
    best = cost[np.arange(n), rows].sum(axis=1).min()
    assert (row >= 0).all()
    assert any(np.array_equal(row, r) for r in rows)  # a valid configuration
    assert cost[np.arange(n), row].sum() == pytest.approx(best)


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(GOAL_KINDS), st.integers(1, 3), st.integers(1, 3), st.integers(0, 2**32))
def test_holds_exactly_when_some_configuration_is_realised(kind, n, m, seed):
    rng = np.random.default_rng(seed)
    if kind.distinct and m < n:
        m = n
    caps = _capacities(kind, m, n, rng)
    goals = rng.uniform(0, 6, size=(m, 2))
    positions = goals[rng.integers(0, m, size=n)] + rng.normal(0, 0.8, size=(n, 2))
    near = np.hypot(*(positions[:, None] - goals[None]).transpose(2, 0, 1)) <= 1.0
    rows = kind.configurations(n, m, caps)
    brute = bool(near[np.arange(n), rows].all(axis=1).any())
    assert kind.holds(positions, goals, 1.0, caps) == brute


@given(st.sampled_from((RENDEZVOUS, ALLOCATION)), st.lists(st.integers(0, 3), max_size=6))
def test_pins_admitted_one_by_one_stay_a_part_of_a_valid_configuration(kind, goals):
    pins: dict[int, int] = {}
    for robot, goal in enumerate(goals):
        if kind.admits(pins, goal):
            pins[robot] = goal
    chosen = list(pins.values())
    if kind.gathers:
        assert len(set(chosen)) <= 1
    else:
        assert len(set(chosen)) == len(chosen)
    # and whatever was refused would have broken that
    for goal in range(4):
        extended = [*chosen, goal]
        fits = len(set(extended)) <= 1 if kind.gathers else len(set(extended)) == len(extended)
        assert kind.admits(pins, goal) == fits


def test_the_capacity_laws_count_what_they_list():
    for n, m in itertools.product(range(1, 4), range(1, 4)):
        for caps in itertools.product(range(n + 1), repeat=m):
            if sum(caps) == n:
                assert CAPACITY.count(n, m, caps) == len(CAPACITY.configurations(n, m, caps))


def test_a_joint_mission_runs_in_the_one_loop_and_refuses_mixed_communication():
    from epistemica.sim import simulate
    from epistemica.sim.kinds.collaborative import CollaborativeScenario

    s = CollaborativeScenario.drawn(robots=3, needs=(2,), seed=2).replace(max_steps=40)
    trial = simulate(s, "rules", seed=2)
    assert trial.steer_to.shape == (trial.steps, 3) and trial.unpruned is None
    assert trial.knows.shape == (trial.steps, 3, 1) and trial.aware_since.shape == (3, 3, 1)
    # a teammate that shares everything and one that shares nothing see different worlds
    with pytest.raises(InvalidArgumentError, match="share") as caught:
        simulate(s, "rules", seed=2, policies={0: "oracle"})
    assert "one level" in caught.value.hint
