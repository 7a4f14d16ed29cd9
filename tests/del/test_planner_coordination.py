"""Implicit coordination on the shipped two-robot problem (specs/planning)."""

from __future__ import annotations

from pathlib import Path

import pytest

from epistemica.del_ import (
    InvalidArgumentError,
    check_implicit_coordination,
    load_spec,
    plan,
    plan_implicitly_coordinated,
    validate,
)
from epistemica.del_.planning.coordination import perspective

SPEC = Path(__file__).resolve().parents[2] / "specs" / "planning" / "two_robots_implicit.epi"


@pytest.fixture(scope="module")
def problem():
    spec = load_spec(SPEC)
    owners = {name: name.split("_")[1] for name in spec.actions}  # go_r1_g1 -> r1
    return spec, owners


def test_coordinated_plan_is_found_and_checked(problem):
    spec, owners = problem
    found = plan_implicitly_coordinated(spec.model, spec.actions, owners, spec.goal)
    assert found == ["go_r1_g1", "go_r2_g2"]
    assert check_implicit_coordination(spec.model, spec.actions, owners, found, spec.goal)


def test_valid_but_uncoordinated_plan_and_the_reason(problem):
    spec, owners = problem
    bad = ["go_r2_g2", "go_r1_g1"]
    assert validate(spec.model, spec.actions, bad, spec.goal)  # works in the actual world
    assert plan(spec.model, spec.actions, spec.goal) == bad  # plain BFS is happy with it
    report = check_implicit_coordination(spec.model, spec.actions, owners, bad, spec.goal)
    assert not report
    assert (report.step, report.agent, report.action, report.kind) == (
        1, "r1", "go_r1_g1", "not-applicable",
    )  # fmt: skip
    # the breaking world is one where r1's task is g2, brought in by r2 at step 0
    assert "target1" not in spec.model.valuation_of(report.world[0])
    ((step, agent, _world, actual),) = report.chain
    assert (step, agent) == (0, "r2")
    assert "target1" in spec.model.valuation_of(actual)
    assert "r2" in report.reason and "go_r1_g1" in report.reason


def test_goal_failure_is_reported(problem):
    spec, owners = problem
    report = check_implicit_coordination(spec.model, spec.actions, owners, ["go_r1_g1"], spec.goal)
    assert not report and report.kind == "goal" and report.chain == ()


def test_perspective_and_bad_owners(problem):
    spec, _ = problem
    assert len(perspective(spec.model, "r2").designated) == 2
    assert len(perspective(spec.model, "r1").designated) == 1
    with pytest.raises(InvalidArgumentError):
        check_implicit_coordination(spec.model, spec.actions, {}, [], spec.goal)
    with pytest.raises(InvalidArgumentError):
        perspective(spec.model, "r9")
