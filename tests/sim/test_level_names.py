"""The level switch (issue 37): ``first``, ``second``, ``third`` are the planning
controller, the rules' one-step controller keeps every name under ``rules-``, the prior-mode
ablations play the same trial with or without the planner, and the environments' default
teammates are the rules' level their measured results name."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.env import RobotEnv
from epistemica.sim.kinds.registry import KINDS
from epistemica.sim.policies.active import ORDERS, ActiveInference
from epistemica.sim.policies.collaborative_levels import CollaborativePolicy
from epistemica.sim.policies.collaborative_planning import PlanningCollaborativePolicy
from epistemica.sim.policies.levels import (
    JOINT_LEVELS,
    KIND_LEVELS,
    LEVELS,
    make_level,
    make_policy,
    rules_level,
)
from epistemica.sim.study.palette import level_style

ROOT = Path(__file__).resolve().parents[2]
PRIVATE = ROOT / "specs" / "nested" / "private_goal_3.epi"
ACTIVE = [
    name
    for name in LEVELS
    if name != "convention+rules" and isinstance(make_policy(name), ActiveInference)
]


@pytest.mark.parametrize("name", ACTIVE)
def test_every_active_level_is_named_by_what_it_is(name):
    policy = make_policy(name)
    p = policy.parameters
    assert policy.name == name  # the controller names itself as the registry does
    # the planner has the bare names, the rules' one-step controller the prefix rules-;
    # the prior's mode bypasses both (one name)
    if not p.free_energy:
        assert name.endswith("-priormode") and not name.startswith("rules-")
    else:
        assert p.planning == (not name.startswith("rules-"))
    assert name.removeprefix("rules-").split("-")[0] in ORDERS


def test_the_orders_and_ablations_have_both_controllers():
    for order in ORDERS:
        assert make_policy(order).parameters.planning
        assert not make_policy(f"rules-{order}").parameters.planning
        assert make_policy(order).order == make_policy(f"rules-{order}").order == ORDERS[order]
    for ablation in ("second-shared", "third-shared", "first-unpruned", "third-unpruned"):
        planner, rules = make_policy(ablation), make_policy(f"rules-{ablation}")
        assert planner.parameters.planning and not rules.parameters.planning
        assert planner.parameters.replace(planning=False) == rules.parameters
    assert make_policy("third-wait").parameters.plan_horizon == 3
    # the planner's horizon is over options: its default plans one, and no -myopic level
    # repeats it (the myopic controller, one control ahead, is rules-third)
    assert make_policy("third").parameters.plan_horizon == 1
    assert not any(name.endswith("-myopic") for name in LEVELS)
    assert not any(name.startswith("plan-") for name in (*LEVELS, *JOINT_LEVELS))


@pytest.mark.parametrize("order", [1, 3])
def test_the_prior_mode_plays_the_same_trial_with_or_without_the_planner(order):
    # free_energy=False bypasses the planner (ControllerStage.act, _decide_nested), so the
    # registered -priormode (planning=True) and the rules' controller without expected
    # free energy move every robot alike, on a mission whose events nest the sets. (Only a
    # rendezvous search that meets another group can differ: plan_meet's search end is the
    # planner levels', the ablation included; no search on these seeds.)
    mission = load_mission(PRIVATE)
    name = {v: k for k, v in ORDERS.items()}[order] + "-priormode"
    for seed in range(3):
        s = mission.scenario(seed)
        rules = ActiveInference(order, mission.parameters, free_energy=False)
        assert not rules.parameters.planning and rules.name == name
        a = simulate(s, name, seed=seed, parameters=mission.parameters)
        b = simulate(s, rules, seed=seed)
        assert np.array_equal(a.trajectory, b.trajectory)
        assert (a.success, a.steps) == (b.success, b.steps)


def test_the_collaborative_levels_are_the_planner_and_the_rules():
    for name in ("first", "second", "third", "third-shared", "third-priormode"):
        assert type(make_level("collaborative", name)) is PlanningCollaborativePolicy
    expected = {"rules": "third", "rules-first": "first", "rules-shared": "shared"}
    for name, style in expected.items():
        policy = make_level("collaborative", name)
        assert type(policy) is CollaborativePolicy and policy.style == style
    assert make_level("collaborative", "third").order == 3


def test_an_environments_teammates_default_to_the_rules_level():
    assert (rules_level("allocation"), rules_level("collaborative")) == ("rules-third", "rules")
    env = RobotEnv(load_mission(PRIVATE))
    assert set(env.multi.scripted.values()) == {"rules-third"}
    tasks = load_mission(ROOT / "specs" / "collaborative" / "tasks_3.epi")
    assert set(RobotEnv(tasks).multi.scripted.values()) == {"rules"}


def test_the_help_says_which_level_is_which_and_names_only_real_levels(capsys):
    from epistemica.cli import main

    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = capsys.readouterr().out
    goal, joint = text.split("collaborative missions")
    assert "the planning controller" in goal and "the rules' one-step controller" in goal
    assert "the planning controller" in joint and "the rules (third," in joint
    for name in ("rules-first", "rules-second", "rules-third", "third-wait", "convention+rules"):
        assert name in goal and name in LEVELS
    for name in ("rules", "rules-first", "rules-shared", "third-priormode", "oracle-events"):
        assert name in joint and name in JOINT_LEVELS


def test_every_registered_level_has_a_style_of_its_own():
    names = {name for table in KIND_LEVELS.values() for name in table}
    styles = {name: level_style(name) for name in names}
    assert len(set(styles.values())) == len(names)
    # The main job's bars (private_goal_3) and every kind's default study: one colour each.
    main_job = ("convention", "rules-first", "rules-third-shared", "rules-third", "third")
    for shown in (main_job, *(kind.study_levels for kind in KINDS.values())):
        assert len({styles[name][0] for name in shown}) == len(shown), shown
