"""Mission files: compilation, shipped specs, located errors and mutated input."""

from __future__ import annotations

import re
from pathlib import Path
from unittest.mock import patch

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from epistemica.cli.run import is_mission_file
from epistemica.del_ import KnowledgeStructure, parse_formula
from epistemica.del_.errors import EpistemicaError, SourceError
from epistemica.del_.state.explicit import knowledge_mask
from epistemica.mission import Mission, load_mission, parse_mission
from epistemica.sim import Scenario, simulate
from epistemica.sim.engine.worlds import (
    ConfigurationTable,
    configuration_model,
    configuration_structure,
)

ROOT = Path(__file__).resolve().parents[1]
MISSIONS = sorted(p for p in ROOT.glob("specs/**/*.epi") if is_mission_file(str(p)))
SHIPPED = [p for p in MISSIONS if p.parent.name != "stress"]  # not the generated stress suite

TWO = """\
mission allocation
robot a: range at (5, 5)
robot b: bearing at (25, 5)
goal x at (5, 20)
goal y at (25, 20)
"""


def test_the_shipped_missions_are_found():
    names = {p.stem for p in SHIPPED}
    assert len(MISSIONS) == len(SHIPPED) + 110  # the stress suite
    assert {"rendezvous", "task_allocation", "multi_task", "heterogeneous", "capacity"} <= names
    assert {"door_closes", "relocated_goal", "private_message"} <= names
    assert "sensing_radius" in names


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.stem)
def test_shipped_missions_compile_and_their_claims_hold(path):
    mission = load_mission(path)
    scenario = mission.scenario()
    assert scenario.n_robots == len(mission.robots)
    assert scenario.robot_names == mission.robots
    if mission.checks:
        assert mission.model.n_worlds >= mission.configurations().shape[0]
        for claim in mission.checks:
            model = mission.model
            if claim.after is not None:
                model = mission.model_after(claim.after, claim.seed, claim.level)
            assert mission.holds(claim.check.formula, model) == claim.check.expected
    if mission.kind.joint:  # its trials: tests/test_collaborative_mission.py
        trial = mission.trial(5, seed=1, level="convention")
    else:
        trial = simulate(scenario.replace(max_steps=5), "convention", seed=1)
    assert trial.steps <= 5


def test_too_many_configurations_for_a_list_are_a_knowledge_structure():
    mission = load_mission(ROOT / "specs" / "stress" / "allocation_honest_10.epi")
    model = mission.model  # 10! = 3,628,800 allocations, never listed
    assert isinstance(model, KnowledgeStructure)
    assert mission.holds("~K[r1] assigned(r1, g1) & K[r1] ~(assigned(r1, g1) & assigned(r2, g1))")


SMALL = ("capacity", "sensing_radius", "door_closes", "relocated_goal", "private_message")


@pytest.mark.parametrize("path", [p for p in SHIPPED if p.stem in SMALL], ids=lambda p: p.stem)
def test_the_symbolic_model_gives_the_explicit_verdicts(path):
    mission = load_mission(path)
    knowledge = mission.trial(8, 0).knowledge
    p, robots, goals = mission.parts, mission.robots, mission.goals
    rows = mission.configurations()
    explicit = configuration_model(robots, goals, rows, knowledge.state)
    constraints = p.valid + p.initially
    symbolic = configuration_structure(
        mission.kind, robots, goals, knowledge.state, p.capacities, constraints
    )
    formulas = [c.check.formula for c in mission.checks]
    for i, r in enumerate(robots):
        other = robots[(i + 1) % len(robots)]
        for g in goals:
            formulas += [
                parse_formula(f"K[{r}] assigned({r}, {g})"),
                parse_formula(f"B[{r}] ~B[{other}] assigned({other}, {g})"),
                parse_formula(f"C[{r}, {other}] ~assigned({r}, {g})"),
            ]
    for f in formulas:
        assert mission.holds(f, explicit) == mission.holds(f, symbolic), f


def test_worlds_are_the_valid_configurations():
    mission = parse_mission(TWO + "valid ~assigned(a, y)\n")
    assert mission.configurations().tolist() == [[0, 1]]
    assert mission.model.n_worlds == 1
    assert mission.holds("C[a, b] (assigned(a, x) & assigned(b, y))")


def test_a_capacity_mission_has_the_hand_counted_configurations():
    # Three robots, g2 needs two: the robot at g1 is any of the three.
    mission = load_mission(ROOT / "specs" / "capacity.epi")
    rows = mission.configurations()
    assert sorted(map(tuple, rows.tolist())) == [(0, 1, 1), (1, 0, 1), (1, 1, 0)]


def test_learns_is_a_private_announcement():
    mission = parse_mission(TWO + "learns a: assigned(a, x)\n")
    assert mission.holds("K[a] assigned(b, y)")
    assert not mission.holds("K[b] assigned(b, y)")
    assert not mission.holds("K[b] (K[a] assigned(a, x) | K[a] ~assigned(a, x))")
    told = mission.scenario().told
    assert [observers for observers, _ in told] == [(True, False)]


def test_initially_is_common_knowledge():
    mission = parse_mission(TWO + "initially assigned(b, y)\n")
    assert mission.holds("C[a, b] assigned(a, x)")


def test_random_places_come_from_the_trial_seed():
    text = "mission rendezvous\nrobot a: range at random\nrobot b: range at (1, 1)\n"
    mission = parse_mission(text + "goal x at random\n")
    one, again, other = mission.scenario(4), mission.scenario(4), mission.scenario(5)
    assert np.array_equal(one.starts, again.starts) and np.array_equal(one.goals, again.goals)
    assert not np.array_equal(one.goals, other.goals)
    assert one.starts[1].tolist() == [1.0, 1.0, 0.0]
    assert np.all((one.goals >= 1) & (one.goals <= 29))


@pytest.mark.parametrize("seed", [0, 1, 7])
def test_the_shipped_rendezvous_is_the_published_protocol(seed):
    mission = load_mission(ROOT / "specs" / "rendezvous.epi")
    ours, paper = mission.scenario(seed), Scenario.paper("rendezvous", 3, 3, seed=seed)
    assert ours.sensors == paper.sensors
    assert np.array_equal(ours.starts, paper.starts)
    assert np.array_equal(ours.goals, paper.goals)


def test_ranges_declare_several_robots_and_goals():
    mission = parse_mission("mission allocation\nrobot a1..a3: range at random\n"
                            "goal g2..g4 at random\n")  # fmt: skip
    assert mission.robots == ("a1", "a2", "a3") and mission.goals == ("g2", "g3", "g4")


def test_an_event_teaches_its_observers_and_they_know_who_else_saw_it():
    # hand-worked: a is 15 m from x when the door shuts at step 0, b 25 m: only a is near
    mission = parse_mission(TWO + "goal z at (15, 28)\nevent shut { when step 0 closes x "
                            "announces closed(x) full robots if near(x, 16) }\n")  # fmt: skip
    knowledge = mission.trial(1, 0, "convention").knowledge
    model = mission.model_of(knowledge)
    assert mission.holds("K[a] closed(x) & ~K[b] closed(x) & K[a] ~K[b] closed(x)", model)
    assert (
        mission.holds("B[b] ~closed(x) & ~B[b] closed(x) & K[b] ~K[a] closed(x)", model) is False
    )  # b does not know whether a saw it: it thinks a does not know (a belief)
    assert mission.holds("B[b] ~K[a] closed(x)", model)


def test_a_goal_opened_at_a_step_is_seen_open_at_that_step():
    # a stands 3 m from z, within discovery range, when an event opens z at step 0: it sees
    # the world as the event left it, never z closed (a known closing is for good); b,
    # 20 m away, knows nothing of z, and a knows it
    mission = parse_mission(TWO + "goal z at (5, 8) closed\nknows a, b: x, y\n"
                            "sensing range 10 discovery 4\n"
                            "event open { when step 0 opens z reveals z "
                            "full robots if near(z, 5) }\n")  # fmt: skip
    model = mission.model_of(mission.trial(1, 0, "convention").knowledge)
    assert mission.holds("~B[a] closed(z) & B[a] B[b] closed(z)", model)


def test_ranges_keep_their_zero_padding_as_in_spec_files():
    mission = parse_mission(
        "mission rendezvous\nrobot r01..r03: range at random\n"
        'goal g1 at random\ncheck "c": ~K[r01] ~assigned(r03, g1)\n'
    )
    assert mission.robots == ("r01", "r02", "r03")
    assert mission.holds(mission.checks[0].check.formula)


def test_random_knowledge_and_an_ad_hoc_teammate_are_drawn_per_trial():
    text = TWO + "knows random\nteammate random follows zero\n"
    mission = parse_mission(text)
    drawn = [mission.scenario(s).known_goals for s in range(20)]
    assert all(k.any(axis=0).all() for k in drawn)  # every goal known to someone
    assert len({k.tobytes() for k in drawn}) > 1
    assert np.array_equal(
        mission.scenario(3).known_goals, parse_mission(text).scenario(3).known_goals
    )
    robots = {next(iter(mission.policies(s))) for s in range(20)}
    assert robots == {0, 1} and mission.policies(4) == mission.policies(4)


def test_the_study_line():
    mission = parse_mission(
        TWO + "simulate trials 7 seed 3 levels convention, rules_third_unpruned\n"
    )
    assert (mission.study.trials, mission.study.seed) == (7, 3)
    assert mission.study.levels == ("convention", "rules-third-unpruned")


BAD = [
    # (text appended to TWO or whole text, message fragment, line, column)
    (TWO + "learns c: assigned(a, x)\n", "unknown robot 'c'", 6, 8),
    (TWO + 'check "x": K[a] assigned(a, z)\n', "unknown goal 'z'", 6, 29),
    (TWO + "goal x at (1, 1)\n", "goal 'x' is declared twice", 6, 6),
    (TWO + "valid assigned(a, x) & assigned(b, x)\n", "no configuration satisfies", 1, 1),
    (TWO.replace("(25, 5)", "(45, 5)"), "outside the workspace", 3, 7),
    (TWO + "sensing noise -0.5\n", "outside [0, 1e+06]", 6, 15),
    (TWO + "event settle seen by everybody\n", "unknown observer rule 'everybody'", 6, 22),
    (TWO.replace("bearing", "lidar"), "unknown sensor 'lidar'", 3, 10),
    (TWO + "simulate levels fourth\n", "unknown reasoning level 'fourth'", 6, 17),
    (TWO.replace("mission allocation\n", ""), "no 'mission' line", 5, 1),
    (TWO + "goal z at (1, 1) needs 2\n", "'needs' in a allocation mission", 6, 24),
    (TWO + "valid K[a] assigned(a, x)\n", "cannot speak of knowledge", 6, 9),
    (TWO + "workspace 1" + "0" * 50 + "\n", "number of 51 characters", 6, 11),
    (TWO + "robot and: range at (1, 1)\n", "reserved word", 6, 7),
    (TWO + "mision rendezvous\n", "did you mean 'mission'", 6, 1),
    (TWO + "robot r3..r1: range at (1, 1)\n", "empty range from 3 to 1", 6, 11),
    (TWO + "teammate a follows fifth\n", "unknown reasoning level 'fifth'", 6, 20),
    (TWO + "knows random\nknows a: x\n", "exclude each other", 8, 1),
    # events: unknown names, triggers that never fire, quantities the simulator lacks
    (
        TWO + "event e { when c settles at x suggests assigned(a, x) full robots }\n",
        "unknown robot 'c'",
        6,
        16,
    ),
    (
        TWO + "event e { when step 5 announces assigned(a, z) full robots }\n",
        "unknown goal 'z'",
        6,
        45,
    ),
    (
        TWO + "event e { when step 5 announces open(x) full robots }\n",
        "'open' is not a fact of missions",
        6,
        33,
    ),
    (TWO + "event e { when step 500 closes x full robots }\n", "never fires", 6, 21),
    (
        TWO + "event e { when step 5 closes x full robots if temperature(a) }\n",
        "not a quantity the simulator has",
        6,
        47,
    ),
    (
        TWO + "event e { when step 5 senses assigned(a, x) full robots }\n",
        "not a fact a robot can sense",
        6,
        30,
    ),
    (TWO + "event e { when step 5 closes x }\n", "has no observer", 6, 7),
    (
        TWO + "event e(r in robots) { when step 5 closes x full r }\n",
        "not bound by the trigger",
        6,
        7,
    ),
    (TWO + "event e { closes x full robots }\n", "has no 'when'", 6, 7),
    (TWO + "event flood seen by nearby\n", "unknown library event 'flood'", 6, 7),
    (TWO + "policy lone_wayt 5\n", "did you mean 'lone_wait'", 6, 8),
    (TWO + "policy memory 3\n", "memory must lie in [0, 1]", 6, 8),
    (TWO + "policy memory abc\n", "memory must be a number", 6, 8),
    (TWO + "policy pruning maybe\n", "pruning must be true or false", 6, 8),
    (TWO + "policy revision latest\n", "revision must be one of recency, primacy", 6, 8),
    (
        TWO + 'check "c" after 3 steps level sixth: K[a] assigned(a, x)\n',
        "unknown reasoning level 'sixth'",
        6,
        31,
    ),
    (TWO.replace("workspace", "") + "workspace 1.5\ngoal z at random\n", "no room", 1, 9),
]


@pytest.mark.parametrize(("text", "fragment", "line", "column"), BAD)
def test_bad_missions_are_located_with_a_hint(text, fragment, line, column):
    with pytest.raises(SourceError) as info:
        parse_mission(text, "bad.epi")
    message = str(info.value)
    assert fragment in message
    assert message.startswith(f"bad.epi:{line}:{column}: error:"), message
    assert "hint:" in message
    if info.value.source is not None and line <= len(text.splitlines()):
        assert re.search(r"\n {4}.*\n {4} *\^", message), "no caret under the line"


def _tokens(text: str) -> list[str]:
    return re.findall(r"[A-Za-z_][A-Za-z0-9_]*|-?[0-9.]+|\"[^\"\n]*\"|\S", text)


@settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(st.sampled_from(SHIPPED), st.data())
def test_mutated_missions_compile_or_fail_cleanly(path, data):
    tokens = _tokens(path.read_text())
    for _ in range(data.draw(st.integers(1, 3))):
        i = data.draw(st.integers(0, len(tokens) - 1))
        action = data.draw(st.sampled_from(["delete", "insert", "swap", "truncate"]))
        if action == "delete":
            del tokens[i]
        elif action == "insert":
            tokens.insert(i, data.draw(st.sampled_from([*tokens, "(", ",", "at", "9e99"])))
        elif action == "swap":
            j = data.draw(st.integers(0, len(tokens) - 1))
            tokens[i], tokens[j] = tokens[j], tokens[i]
        else:
            tokens = tokens[:i]
        if not tokens:
            tokens = ["mission"]
    try:
        mission = parse_mission(" ".join(tokens), "mutant.epi")
    except EpistemicaError:
        return
    mission.scenario()  # a mission that compiles is a valid simulator world


AFTER = [p for p in SHIPPED if not load_mission(p).kind.tasks]


@pytest.mark.parametrize("path", AFTER, ids=lambda p: p.stem)
@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 40), steps=st.integers(1, 25), data=st.data())
def test_check_after_agrees_with_what_the_robots_knew(path, seed, steps, data):
    """The model `check --after` builds and the knowledge the simulated robots acted on
    give the same answers: B[i] f and K[i] f, and B[i] B[j] f, for every robot and goal."""
    mission = load_mission(path)
    level = data.draw(st.sampled_from(mission.study.levels))
    trial = mission.trial(steps, seed, level)
    knowledge = trial.knowledge
    real = Mission.trial

    def run_once(self, *args):  # model_after's own run of this trial is the one just run
        return trial if self is mission and args == (steps, seed, level) else real(self, *args)

    with patch.object(Mission, "trial", run_once):
        model = mission.model_after(steps, seed, level)
    rows = mission.configurations()
    robots, goals = mission.robots, mission.goals
    i, j = data.draw(st.integers(0, len(robots) - 1)), data.draw(st.integers(0, len(robots) - 1))
    believed = knowledge.possible((i,), rows)
    nested = knowledge.possible((i, j), rows)
    known = knowledge_mask(knowledge.state, (i,), ConfigurationTable(rows, robots, goals))
    for r in range(len(robots)):
        for g in range(len(goals)):
            fact = f"assigned({robots[r]}, {goals[g]})"
            on = rows[:, r] == g
            assert mission.holds(f"B[{robots[i]}] {fact}", model) == bool(on[believed].all())
            assert mission.holds(f"K[{robots[i]}] {fact}", model) == bool(on[known].all())
            pair = f"B[{robots[i]}] B[{robots[j]}] {fact}"
            assert mission.holds(pair, model) == bool(on[nested].all())
