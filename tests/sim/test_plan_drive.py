"""``plan_drive``: the planner's stationary type drives to a goal before it stands (aif.md §6g)."""

from __future__ import annotations

import pytest

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.policies.parameters import ActiveParameters


def test_plan_drive_is_off_by_default_and_a_switch():
    assert ActiveParameters().plan_drive is False
    assert ActiveParameters(plan_drive=True).plan_drive is True
    with pytest.raises(InvalidArgumentError, match="plan_drive"):
        ActiveParameters(plan_drive=1)
