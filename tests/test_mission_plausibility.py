"""A robot's plausibility order over configurations (the mission line ``plausibility``).

The initial model of a mission with an order is a plausibility model; in the simulator the
order is the robot's prior soft evidence, so that a hard observation that contradicts its
most plausible configurations revises its belief to the most plausible remaining ones.
Every expected value below is worked out by hand in the comments.
"""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica import load_mission, parse_mission
from epistemica.del_ import InvalidArgumentError, Observation, PlausibilityModel, parse_formula
from epistemica.del_.errors import SpecError
from epistemica.sim import Scenario
from epistemica.sim.engine.worlds import fact_mask

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "specs" / "belief" / "closed_goal_revision.epi"


def believed(mission, knowledge, robot=0) -> list[list[str]]:
    """The configurations (goal names in robot order) ``robot`` believes possible."""
    rows = mission.configurations()
    mask = knowledge.possible((robot,), rows)
    return [[mission.goals[g] for g in row] for row in rows[mask].tolist()]


def test_the_example_mission_ranks_as_worked_out():
    m = load_mission(EXAMPLE)
    model = m.model
    assert isinstance(model, PlausibilityModel)
    # One world per configuration (no private facts), r1 ranked by the level r2's goal
    # reaches first: east 0, north 1, west (none of the levels) 2; r2 has no order.
    assert model.n_worlds == 6
    by_world = {}
    for w in range(model.n_worlds):
        true = [a for a, t in zip(model.atoms, model.valuation[w], strict=True) if t]
        r2 = next(a for a in true if a.startswith("assigned(r2"))
        by_world[r2] = by_world.get(r2, set()) | {int(model.ranks["r1"][w])}
    assert by_world == {
        "assigned(r2, east)": {0},
        "assigned(r2, north)": {1},
        "assigned(r2, west)": {2},
    }
    assert set(model.ranks["r2"].tolist()) == {0}
    for claim in m.checks:
        if claim.after is None:
            assert m.holds(claim.check.formula) == claim.check.expected, claim.check.name


def test_the_example_revises_instead_of_emptying():
    m = load_mission(EXAMPLE)
    # At the start r1 believes the rank-0 configurations: r2 at east.
    assert believed(m, m.knowledge()) == [["west", "east"], ["north", "east"]]
    # East closes at step 3, seen by everyone: (west, north) (rank 1) and (north, west)
    # (rank 2) are left; r1 believes the rank-1 one, r2 (no order) both.
    after = m.trial(5, seed=0, level="rules-third").knowledge
    assert believed(m, after) == [["west", "north"]]
    assert believed(m, after, robot=1) == [["west", "north"], ["north", "west"]]
    # The same mission without the order: r1 believes both as well.
    plain = parse_mission(EXAMPLE.read_text().replace("plausibility r1:", "# "), "plain.epi")
    plain_after = plain.trial(5, seed=0, level="rules-third").knowledge
    assert believed(plain, plain_after) == [["west", "north"], ["north", "west"]]


#: Two robots and three goals, the world of the missions below.
TWO_AND_THREE = """
robot r1: range at (5, 5)
robot r2: range at (25, 5)
goal g1 at (3, 25)
goal g2 at (27, 25)
goal g3 at (15, 28)
"""

RENDEZVOUS = (
    "mission rendezvous\n"
    + TWO_AND_THREE
    + """
plausibility r1: assigned(r1, g1), assigned(r2, g2)
event g1_shuts {
    when step 2
    announces closed(g1)
    full r2
}
event a_hint {
    when step 4
    suggests assigned(r1, g2)
    full r1
}
event g2_shuts {
    when step 6
    announces closed(g2)
    full r1
}
event g3_only {
    when step 8
    announces assigned(r1, g3)
    full r1
}
simulate steps 20 levels rules_third
"""
)


@pytest.mark.parametrize(
    ("steps", "r1_believes", "r2_believes"),
    [
        # Rendezvous configurations: everyone at g1, g2 or g3. r1 ranks g1 0, g2 1, g3 2.
        (1, [["g1", "g1"]], [["g1", "g1"], ["g2", "g2"], ["g3", "g3"]]),
        # g1 shuts, seen by r2 only: r1 is oblivious and keeps g1; r2 keeps g2, g3.
        (3, [["g1", "g1"]], [["g2", "g2"], ["g3", "g3"]]),
        # A hint that r1 goes to g2 (soft, newer than the order): r1 believes g2.
        (5, [["g2", "g2"]], [["g2", "g2"], ["g3", "g3"]]),
        # g2 shuts, seen by r1: the hint is contradicted and dropped; of the order, the
        # most plausible configuration r1 cannot rule out is g1 (it did not see g1 shut).
        (7, [["g1", "g1"]], [["g2", "g2"], ["g3", "g3"]]),
        # r1 learns it goes to g3: neither level is left, so it believes the rest, g3.
        (9, [["g3", "g3"]], [["g2", "g2"], ["g3", "g3"]]),
    ],
)
def test_the_order_decides_the_belief_before_and_after_events(steps, r1_believes, r2_believes):
    m = parse_mission(RENDEZVOUS, "rendezvous.epi")
    knowledge = m.trial(steps, seed=0).knowledge
    assert believed(m, knowledge) == r1_believes
    assert believed(m, knowledge, robot=1) == r2_believes
    if steps < 4:  # the order's levels are no sighting of a teammate settled (the hint is)
        assert knowledge.settled((0,)) == []
    else:
        assert knowledge.settled((0,)) == [(0, 1)]


def test_a_private_fact_gives_the_plausibility_model_cells():
    # r1 learns privately that r2 is not at g3 (allocation, 2 robots, 3 goals: 6 configs).
    # The group model has the actual copy (the fact holds: 4 configs) and r2's copy (r2
    # does not know r1 was told: 6 configs). r2's cell holds both copies, r1's cell is
    # its copy, where it believes r2 at g1 (copy 0) or at g3 (copy 1). r1's order ranks
    # r2 at g3 first: excluded in its actual cell, so it believes the next level, r2 at g1.
    m = parse_mission(
        "mission allocation\n"
        + TWO_AND_THREE
        + """
        learns r1: ~assigned(r2, g3)
        plausibility r1: assigned(r2, g3), assigned(r2, g1)
        plausibility r2: assigned(r2, g2)
        check "r1 believes r2 goes to g1": B[r1] assigned(r2, g1)
        check "r2 believes it goes to g2": B[r2] assigned(r2, g2)
        check "r2 cannot tell whether r1 was told, nor what r1 believes":
            ~B[r2] B[r1] assigned(r2, g1) & ~B[r2] B[r1] assigned(r2, g3)
        check "were r2 at g2, r1 would expect r1 at g1 or g3":
            B[r1 | assigned(r2, g2)] (assigned(r1, g1) | assigned(r1, g3))
        """,
        "private.epi",
    )
    assert m.model.n_worlds == 4 + 6
    for claim in m.checks:
        assert m.holds(claim.check.formula) == claim.check.expected, claim.check.name
    assert believed(m, m.knowledge()) == [["g2", "g1"], ["g3", "g1"]]
    assert believed(m, m.knowledge(), robot=1) == [["g1", "g2"], ["g3", "g2"]]


MISSION = """mission allocation
robot r1: range at (5, 5)
robot r2: range at (25, 5)
goal g1 at (3, 25)
goal g2 at (27, 25)
"""


@pytest.mark.parametrize(
    ("line", "message", "column"),
    [
        ("plausibility r3: assigned(r1, g1)", "unknown robot 'r3'", 14),
        ("plausibility r1: at(r1, g1)", "unknown atom 'at'", 18),
        ("plausibility r1: assigned(r1, g9)", "unknown goal 'g9'", 31),
        ("plausibility r1: K[r2] assigned(r1, g1)", "cannot speak of knowledge", 20),
        ("plausibility r1: [^^assigned(r1, g1)] assigned(r2, g2)", "not part of mission", 18),
        (
            "plausibility r1: assigned(r1, g1)\nplausibility r2, r1: assigned(r1, g2)",
            "a second plausibility order for robot 'r1'",
            18,
        ),
        ("knows r1: g1\nplausibility r1: assigned(r1, g1)", "with 'knows' lines", 14),
        (
            'plausibility r1: assigned(r1, g1)\ncheck "c": C[r1, r2] assigned(r1, g1)',
            "uses C[...]",
            7,
        ),
        (
            'plausibility r1: assigned(r1, g1)\ncheck "c" after 2 steps: Sb[r1] assigned(r1, g1)',
            "conditional belief, safe belief or an upgrade",
            7,
        ),
    ],
)
def test_bad_plausibility_lines_are_located(line, message, column):
    text = MISSION + line + "\n"
    with pytest.raises(SpecError) as error:
        parse_mission(text, "bad.epi")
    assert message in error.value.message
    assert error.value.line == text[: text.index(line)].count("\n") + 1 + line.count("\n")
    assert error.value.column == column


def test_an_order_over_too_many_configurations_is_refused_at_its_line():
    # 9 robots, 9 goals: 9! = 362,880 allocations, beyond the explicit limit of 200,000.
    text = "mission allocation\n" + "".join(
        f"robot r{i}: range at ({i + 1}, 2)\ngoal g{i} at ({i + 1}, 20)\n" for i in range(9)
    )
    m = parse_mission(text + "plausibility r0: assigned(r0, g0)\n", "big.epi")
    with pytest.raises(SpecError, match="too many for a plausibility model") as error:
        _ = m.model
    assert (error.value.line, error.value.column) == (
        20,
        14,
    )  # after the mission line and 18 of robots and goals


def test_an_order_in_a_multitask_mission_is_refused():
    text = "mission multitask\nrobot r1: range at (5, 5)\ntask t1 at (3, 25)\n"
    with pytest.raises(SpecError, match="no configurations to rank"):
        parse_mission(text + "plausibility r1: assigned(r1, t1)\n", "bad.epi")


# -- the simulator's belief is the plausibility model's, after hard announcements -------

ROBOTS, GOALS = ("r1", "r2", "r3"), ("g1", "g2", "g3")
ATOMS = [f"assigned({r}, {g})" for r in ROBOTS for g in GOALS]

literals = st.sampled_from(ATOMS).flatmap(lambda a: st.sampled_from([a, f"~{a}"]))
facts = st.one_of(
    literals,
    st.tuples(literals, literals, st.sampled_from(["&", "|"])).map(
        lambda t: f"({t[0]} {t[2]} {t[1]})"
    ),
)


@settings(max_examples=60, deadline=None)
@given(
    kind=st.sampled_from(["allocation", "rendezvous"]),
    levels=st.lists(facts, min_size=1, max_size=4),
    events=st.lists(
        st.tuples(facts, st.sets(st.sampled_from(ROBOTS), min_size=1)), min_size=0, max_size=5
    ),
    actual=st.integers(0, 10_000),
    question=facts,
)
def test_simulator_belief_is_the_most_plausible_after_announcements(
    kind, levels, events, actual, question
):
    text = "\n".join(
        [f"mission {kind}"]
        + [f"robot {r}: range at ({5 + 5 * i}, 5)" for i, r in enumerate(ROBOTS)]
        + [f"goal {g} at ({5 + 8 * j}, 25)" for j, g in enumerate(GOALS)]
        + ["plausibility r1: " + ", ".join(levels)]
    )
    m = parse_mission(text, "random.epi")
    rows = m.configurations()
    world = rows[actual % len(rows)]
    model = m.model  # the plausibility model: here one cell, every configuration
    knowledge = m.knowledge()
    heard = []  # the facts r1 observed, as hard announcements, oldest first
    for i, (fact, observers) in enumerate(events):
        truth = model.restricted(np.ones(model.n_worlds, dtype=bool)).truth(fact)
        at_actual = truth[_world_of(model, world, m)]
        fact = fact if at_actual else f"~{fact}"  # the event happened: true where we are
        knowledge.observe(Observation(f"e{i}", full=observers, pre=fact))
        if "r1" in observers:
            heard.append(fact)
    # The simulator's belief of r1: its B set over the configurations.
    simulated = {tuple(r) for r in rows[knowledge.possible((0,), rows)].tolist()}
    # The plausibility model after [!f] of each fact heard: r1's most plausible worlds.
    after = model
    for fact in heard:
        after = after.restricted(after.truth(fact))
    best = after.best("r1", np.ones(after.n_worlds, dtype=bool))
    expected = {_configuration(after, w, m) for w in np.flatnonzero(best)}
    assert simulated == expected
    # And a belief question answered through the language: [!f1]...[!fk] B[r1] q.
    formula = f"B[r1] {question}"
    for fact in reversed(heard):
        formula = f"[!{fact}] {formula}"
    q_rows = {tuple(r) for r in rows[_rows_satisfying(m, rows, question)].tolist()}
    assert model.holds(formula) == (simulated <= q_rows)


def _configuration(model, w, mission) -> tuple[int, ...]:
    true = {a for a, t in zip(model.atoms, model.valuation[w], strict=True) if t}
    return tuple(
        next(j for j, g in enumerate(mission.goals) if f"assigned({r}, {g})" in true)
        for r in mission.robots
    )


def _world_of(model, row, mission) -> int:
    wanted = tuple(int(g) for g in row)
    return next(w for w in range(model.n_worlds) if _configuration(model, w, mission) == wanted)


def _rows_satisfying(mission, rows, fact) -> np.ndarray:
    return fact_mask(fact, rows, mission.robots, mission.goals)


def test_scenario_suggested_observers_are_checked():
    with pytest.raises(InvalidArgumentError, match="suggested observers must be 2 booleans"):
        Scenario(
            "allocation",
            [[0, 0], [9, 9]],
            [[1, 1], [8, 8]],
            ["range"] * 2,
            suggested=[((True,), parse_formula("assigned(r1, g1)"))],
        )
