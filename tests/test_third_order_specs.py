"""The family where third order decides by construction (specs/third_order/, issue 37).

Each mission is a rendezvous in which some robots see news (a goal revealed, a meeting
place moved) and others do not, so that a witness must predict what another witness
expects of the robots that did not see it: a chain of three robots. The tests check that
the family is what docs/results.md §1b says it is: it parses, its claims hold, the sets the
planner reads differ between chains of length two and three, and in a closed loop
``third`` (the planner at order 3) meets where ``second`` does not.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from epistemica.mission import load_mission

ROOT = Path(__file__).resolve().parents[1]
FAMILY = sorted((ROOT / "specs" / "third_order").glob("*.epi"))
LEVELS = {"second", "third", "rules_third", "convention"}


def test_the_family_has_four_missions_at_three_and_five_robots():
    stems = {p.stem for p in FAMILY}
    names = {s.rsplit("_", 1)[0] for s in stems}
    assert len(names) >= 4
    assert all({f"{n}_3", f"{n}_5"} <= stems for n in names)


@pytest.mark.parametrize("path", FAMILY, ids=lambda p: p.stem)
def test_each_file_explains_itself_and_compares_the_levels(path):
    text = path.read_text()
    comment = [line for line in text.splitlines() if line.startswith("#")]
    assert len(comment) >= 8 and "second order fails" in text
    study = re.search(r"^simulate .*levels (.*)$", text, re.MULTILINE)
    assert study and {lv.strip() for lv in study.group(1).split(",")} >= LEVELS
    mission = load_mission(path)
    assert len(mission.robots) == int(path.stem[-1])
    # Some claim speaks of a chain of three robots' beliefs, after the news.
    chain = re.compile(r"B\[\w+\] ~?B\[\w+\] ~?B\[\w+\]")
    assert any(c.after is not None and chain.search(str(c.check.formula)) for c in mission.checks)


@pytest.mark.parametrize("path", FAMILY, ids=lambda p: p.stem)
def test_the_claims_hold(path):
    mission = load_mission(path)
    assert len(mission.checks) >= 3
    for claim in mission.checks:
        model = mission.model
        if claim.after is not None:
            model = mission.model_after(claim.after, claim.seed, claim.level)
        assert mission.holds(claim.check.formula, model) == claim.check.expected, claim.name


def test_the_chain_of_three_keeps_less_than_the_chain_of_two():
    """What the planner reads (the B sets of the trial's knowledge): after the news of
    late_news_3 (trial 1000: r1 and r3 saw g4), r1 knows r3 keeps meetings at g4, but not
    that r3 thinks r2 does; a second-order robot cuts the chain (r1, r3, r2) to (r1, r3)."""
    mission = load_mission(ROOT / "specs" / "third_order" / "late_news_3.epi")
    trial = mission.trial(5, 1000, "third")
    assert {r for _, name, seen in trial.events for r in seen if name == "news"} == {0, 2}
    rows = mission.configurations()
    at_g4 = (rows == mission.goals.index("g4")).all(axis=1)
    two = trial.knowledge.possible((0, 2), rows)
    three = trial.knowledge.possible((0, 2, 1), rows)
    assert at_g4[two].any() and not at_g4[three].any()
    assert three.any() and set(rows[three].ravel()) < set(rows[two].ravel())


def test_third_order_meets_where_second_order_waits_alone():
    """A few design seeds of late_news_3 where two robots saw the news (under 10 s)."""
    mission = load_mission(ROOT / "specs" / "third_order" / "late_news_3.epi")
    seeds = (1003, 1004, 1005)
    second = [mission.trial(60, s, "second").success for s in seeds]
    third = [mission.trial(60, s, "third").success for s in seeds]
    assert sum(third) - sum(second) >= 2
