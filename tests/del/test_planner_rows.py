"""The planner's per-row memory of conditions (RowTruth) changes the speed only: the same
searches (plans and counts) as the plain evaluator (and see
``test_planner_search.test_every_plan_returned_reaches_the_goal_when_reexecuted``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from epistemica.del_ import load_spec, plan_with_stats
from epistemica.del_.explicit import checker
from epistemica.del_.planning import planner

SPECS = Path(__file__).resolve().parents[2] / "specs" / "planning"


class _PlainEvaluator:
    """Stands in for RowTruth: every truth set from the evaluator, nothing remembered."""

    def __call__(self, model, formula):
        return checker.evaluate(model, formula)


def _counts(result):
    return result.plan, result.expanded, result.generated, result.distinct, result.complete


@pytest.mark.parametrize(
    "name", ["coin_in_the_box_d", "cc_2_2_3_pl4", "grapevine", "selective_communication"]
)
def test_same_search_as_the_plain_evaluator(name, monkeypatch):
    spec = load_spec(SPECS / f"{name}.epi")
    remembered = plan_with_stats(spec.model, spec.actions, spec.goal)
    monkeypatch.setattr(planner, "RowTruth", _PlainEvaluator)
    plain = plan_with_stats(spec.model, spec.actions, spec.goal)
    assert remembered.plan is not None
    assert _counts(remembered) == _counts(plain)
