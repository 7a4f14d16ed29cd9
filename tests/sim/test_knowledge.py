"""TeamKnowledge: soundness of pruning, and agreement with the model checker.

The chain sets of :class:`TeamKnowledge` (the logic layer's epistemic state over
configurations as worlds) are checked against the engine's product update: the same
events, as action models (settles announced to their observers, the others oblivious),
applied to the Kripke model over the valid configurations. When the events are true of
one configuration (no revision needed), ``K[i] K[j] f`` and ``B[i] B[j] f`` hold at the
true world exactly when ``f`` holds on every configuration the chain ``(i, j)`` keeps.
"""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif.configurations import valid_configurations
from epistemica.del_ import KripkeModel, Observation, parse_formula
from epistemica.mission import library_event, load_mission
from epistemica.sim import Scenario, simulate
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.worlds import fact_mask
from epistemica.sim.policies.active import ActiveInference
from epistemica.sim.policies.configuration_sets import nested_sets
from epistemica.sim.policies.levels import make_policy


def settle(knowledge, robot, goal, observers):
    """Robot ``robot`` seen settled at ``goal`` by ``observers`` (n booleans), as the
    library's settle event teaches it."""
    names = {knowledge.robots[i] for i, seen in enumerate(observers) if seen}
    fact = f"assigned({knowledge.robots[robot]}, {knowledge.goals[goal]})"
    return knowledge.observe(Observation("settle", full=names, suggests=fact))


@st.composite
def histories(draw):
    """A mission, its true configuration and a sequence of events consistent with it."""
    n = draw(st.integers(2, 3))
    m = draw(st.integers(n, 3))
    kind = draw(st.sampled_from(["allocation", "rendezvous"]))
    rows = valid_configurations(kind, n, m)
    truth = rows[draw(st.integers(0, rows.shape[0] - 1))]
    robots = [f"r{i + 1}" for i in range(n)]
    goals = [f"g{g + 1}" for g in range(m)]
    events = []
    for _ in range(draw(st.integers(0, 4))):
        observers = draw(st.lists(st.booleans(), min_size=n, max_size=n))
        if draw(st.booleans()):  # a robot seen settled at its true goal
            r = draw(st.integers(0, n - 1))
            events.append(("settle", r, int(truth[r]), observers))
        else:  # a true fact told: some robot does not go to some other goal
            r = draw(st.integers(0, n - 1))
            others = [g for g in range(m) if g != truth[r]]
            if others:
                g = draw(st.sampled_from(others))
                events.append(("tell", r, g, observers))
    return kind, rows, truth, robots, goals, events


def _fact(kind, r, g, robots, goals):
    atom = f"assigned({robots[r]}, {goals[g]})"
    return atom if kind == "settle" else f"~{atom}"


def _replay(rows, robots, goals, events, truth):
    """The team's knowledge, and the reference: the Kripke model over the configurations
    after the events' action models (each fact announced to its observers)."""
    knowledge = TeamKnowledge(robots, goals)
    val = {" ".join(goals[g] for g in row): [f"assigned({robots[i]}, {goals[g]})"
           for i, g in enumerate(row)] for row in rows.tolist()}  # fmt: skip
    worlds = list(val)
    everything = [(u, v) for u in worlds for v in worlds]
    model = KripkeModel(worlds, val, dict.fromkeys(robots, everything), worlds)
    model = model.repoint(" ".join(goals[g] for g in truth))
    for kind, r, g, observers in events:
        fact = _fact(kind, r, g, robots, goals)
        if kind == "settle":
            settle(knowledge, r, g, observers)
        else:
            knowledge.tell(parse_formula(fact), observers)
        names = {robots[i] for i, seen in enumerate(observers) if seen}
        model = model.update(Observation(kind, full=names, pre=fact).action_model(robots))
    return knowledge, model


def rows_satisfying(formula, rows, robots, goals):
    return fact_mask(formula, rows, robots, goals)


@settings(max_examples=60, deadline=None)
@given(histories())
def test_the_true_configuration_is_never_pruned(history):
    _, rows, truth, robots, goals, events = history
    knowledge, _ = _replay(rows, robots, goals, events, truth)
    true_row = np.flatnonzero((rows == truth).all(axis=1))[0]
    for length in (1, 2, 3):
        for chain in itertools.product(range(len(robots)), repeat=length):
            assert knowledge.possible(chain, rows)[true_row]


@settings(max_examples=60, deadline=None)
@given(histories())
def test_a_configuration_is_pruned_only_by_an_observed_event(history):
    _, rows, truth, robots, goals, events = history
    knowledge, _ = _replay(rows, robots, goals, events, truth)
    for i in range(len(robots)):
        kept = knowledge.possible((i,), rows)
        seen = [e for e in events if e[3][i]]
        for row in rows[~kept]:
            contradicted = [
                e
                for e in seen
                if not rows_satisfying(
                    parse_formula(_fact(e[0], e[1], e[2], robots, goals)),
                    row[None],
                    robots,
                    goals,
                )[0]
            ]
            assert contradicted, f"robot {i} pruned {row} without seeing why"


@settings(max_examples=60, deadline=None)
@given(histories(), st.data())
def test_nested_sets_agree_with_the_model_checker(history, data):
    _, rows, truth, robots, goals, events = history
    knowledge, model = _replay(rows, robots, goals, events, truth)
    r = data.draw(st.integers(0, len(robots) - 1))
    g = data.draw(st.integers(0, len(goals) - 1))
    fact = data.draw(st.sampled_from(["", "~"])) + f"assigned({robots[r]}, {goals[g]})"
    for length in (1, 2, 3):
        chain = data.draw(st.lists(st.integers(0, len(robots) - 1), min_size=length,
                                   max_size=length))  # fmt: skip
        on_set = rows_satisfying(parse_formula(fact), rows, robots, goals)
        expected = bool(on_set[knowledge.possible(chain, rows)].all())
        for modality in ("K", "B"):
            prefix = "".join(f"{modality}[{robots[i]}] " for i in chain)
            assert model.holds(prefix + fact) == expected, (prefix + fact, events)


@settings(max_examples=60, deadline=None)
@given(histories())
def test_chains_with_one_signature_keep_one_set(history):
    # possible_many shares one computation among chains of equal signature: that is
    # sound only if the signature determines the set, which this checks chain by chain.
    _, rows, truth, robots, goals, events = history
    knowledge, _ = _replay(rows, robots, goals, events, truth)
    chains = [c for k in (1, 2, 3) for c in itertools.product(range(len(robots)), repeat=k)]
    by_signature = {}
    for chain, kept in zip(chains, knowledge.possible_many(chains, rows), strict=True):
        assert np.array_equal(kept, knowledge.possible(chain, rows))
        first = by_signature.setdefault(knowledge.signature(chain), kept)
        assert np.array_equal(first, kept)


def test_an_oblivious_teammate_keeps_the_larger_set():
    # Hand-worked: robot 0 sees robot 2 settle at goal 1; robot 1 is out of range.
    rows = valid_configurations("allocation", 3, 3)
    k = TeamKnowledge(["r1", "r2", "r3"], ["g1", "g2", "g3"])
    settle(k, 2, 1, [True, False, True])
    assert k.possible((0,), rows).sum() == 2  # r3 at g2: r1 and r2 share g1, g3
    assert k.possible((1,), rows).sum() == 6
    assert k.possible((0, 1), rows).sum() == 6  # r1 knows r2 did not see it
    assert k.possible((0, 2), rows).sum() == 2  # ... and that r3 knows r1 saw it


def test_a_contradictory_settle_is_ignored_not_an_empty_set():
    rows = valid_configurations("rendezvous", 2, 2)
    k = TeamKnowledge(["r1", "r2"], ["g1", "g2"])
    settle(k, 0, 0, [True, True])
    settle(k, 1, 1, [True, True])  # cannot both hold in a rendezvous: the newest wins
    assert k.possible((0,), rows).tolist() == [False, True]


def test_a_settle_seen_again_dates_from_its_first_sighting():
    # Hand-worked: r2 settles at g1, then at g2, then back at g1, all seen by r1. The
    # simulator dates evidence from its first sighting (g2 stays the newest); the logic
    # layer alone takes the third settle as the newest upgrade.
    rows = valid_configurations("rendezvous", 2, 2)
    k = TeamKnowledge(["r1", "r2"], ["g1", "g2"])
    assert settle(k, 1, 0, [True, True]) and settle(k, 1, 1, [True, True])
    assert not settle(k, 1, 0, [True, True])
    assert not settle(k, 1, 0, [True, False])  # fewer observers: nothing new either
    assert k.possible((0,), rows).tolist() == [False, True]
    again = Observation("settle", full={"r1", "r2"}, suggests="assigned(r2, g1)")
    assert k.state.observe(again)
    assert k.possible((0,), rows).tolist() == [True, False]


def test_the_primacy_ablation_keeps_the_first_settle_through_the_nested_sets():
    # Hand-worked: a rendezvous at g1 or g2; r2 is seen settled at g1, then at g2.
    rows = valid_configurations("rendezvous", 2, 2)
    k = TeamKnowledge(["r1", "r2"], ["g1", "g2"])
    settle(k, 1, 0, [True, True])
    settle(k, 1, 1, [True, True])
    newest = nested_sets(k, ["range"] * 2, 0, 2, rows)
    oldest = nested_sets(k, ["range"] * 2, 0, 2, rows, revision="primacy")
    assert newest.own.tolist() == [False, True] and newest.pairs[1].tolist() == [False, True]
    assert oldest.own.tolist() == [True, False] and oldest.pairs[1].tolist() == [True, False]


def test_settle_events_of_a_trial_are_recorded_with_their_observers():
    s = Scenario(
        "allocation",
        [[4, 4], [6, 5], [26, 26]],
        [[5, 8], [12, 4], [24, 22]],
        ["range", "range", "bearing"],
        sensing_range=8.0,
        events=[library_event("settle")],
    )
    trial = simulate(s, "rules-third", seed=0)
    assert trial.success
    settles = [e for e in trial.events if e[1] == "settle"]
    assert {e[2] for e in settles} == {0, 1, 2}
    final = trial.trajectory[-1, :, :2]
    for step, _, robot, goal, observers in settles:
        assert robot in observers
        assert np.hypot(*(final[robot] - s.goals[goal])) <= s.success_radius
        here = trial.trajectory[step, :, :2]
        near = np.flatnonzero(np.hypot(*(here - here[robot]).T) <= 8.0)
        assert set(observers) == set(near.tolist())


def test_nested_sets_that_prune_nothing_leave_the_trial_unchanged():
    # A tautology told to everyone routes every robot through the nested-set decision,
    # whose sets are then the whole table: the trial must equal the plain one.
    base = Scenario.paper("allocation", 3, 3, seed=2)
    told = base.replace(told=[((True,) * 3, parse_formula("assigned(r1, g1) | ~assigned(r1, g1)"))])
    plain, nested = simulate(base, "rules-third", seed=2), simulate(told, "rules-third", seed=2)
    assert np.allclose(plain.trajectory, nested.trajectory, atol=1e-9)
    assert plain.success == nested.success


def test_a_robot_models_a_teammate_over_the_goals_it_knows_the_teammate_knows():
    # Robot 0 alone knows goal 2; in its model of robot 1 (chain (0, 1)) goal 2 is absent.
    known = [[True, True, True], [True, True, False]]
    k = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"], known_goals=known)
    rows = valid_configurations("allocation", 2, 3)
    assert k.possible((0,), rows).sum() == 6
    assert k.possible((0, 1), rows).tolist() == [2 not in r for r in rows.tolist()]
    assert k.private_goals(0) and not k.private_goals(1)


def test_a_robot_that_knows_no_goal_sweeps_until_it_finds_one():
    # Robot 1 knows no goal and the goal is 20 m away: standing still it would never
    # learn of it; sweeping the workspace it discovers it and the rendezvous succeeds.
    s = Scenario(
        "rendezvous",
        [[25.0, 25.0], [5.0, 5.0]],
        [[25.0, 24.0]],
        ["range", "range"],
        known_goals=np.array([[True], [False]]),
        max_steps=150,
    )
    trial = simulate(s, "rules-third", seed=0)
    assert trial.success
    assert np.hypot(*(trial.trajectory[-1, 1, :2] - s.goals[0])) <= s.success_radius


def test_unseen_teammates_meet_at_the_goal_of_the_common_view():
    # Two robots 28 m apart with a 5 m sensing range never see each other. Each is
    # nearest a different corner goal; the third goal is at the centre. From its own view
    # each would pick its own corner; from the common view (nobody's position is common
    # knowledge) both pick the centre goal, and meet.
    s = Scenario(
        "rendezvous",
        [[3.0, 3.0], [27.0, 27.0]],
        [[5.0, 5.0], [25.0, 25.0], [15.0, 15.5]],
        ["range", "range"],
        sensing_range=5.0,
    )
    common = simulate(s, "rules-third", seed=0)
    assert common.success
    end = common.trajectory[-1, :, :2]
    assert np.all(np.hypot(*(end - s.goals[2]).T) <= s.success_radius)
    assert not simulate(s, ActiveInference(3, common_view=False), seed=0).success


@settings(max_examples=60, deadline=None)
@given(st.data())
def test_the_convention_pins_settled_robots_as_the_table_would(data):
    # The convention solves a reduced assignment with the settled robots pinned instead of
    # enumerating every configuration; both must pick the same configuration.
    from epistemica.sim.policies.baselines import Convention

    n = data.draw(st.integers(2, 4))
    kind = data.draw(st.sampled_from(["allocation", "rendezvous"]))
    rng = np.random.default_rng(data.draw(st.integers(0, 10**6)))
    s = Scenario(kind, rng.uniform(0, 30, (n, 2)), rng.uniform(1, 29, (n, 2)), ["range"] * n)
    k = TeamKnowledge(s.robot_names, s.goal_names)
    for _ in range(data.draw(st.integers(1, 3))):
        settle(k, data.draw(st.integers(0, n - 1)), data.draw(st.integers(0, n - 1)), [True] * n)
    view = np.column_stack([rng.uniform(0, 30, (n, 2)), np.zeros(n)])
    goals = np.arange(n)
    pinned = Convention()
    pinned.start(s, np.arange(n), [None] * n)
    pinned._knowledge = k
    tabled = Convention()
    tabled.start(s.replace(valid=s.configurations()), np.arange(n), [None] * n)
    tabled._knowledge = k
    for robot in range(n):
        a = pinned.configuration(view, goals, robot)
        b = tabled.configuration(view, goals, robot)
        assert a[robot] == b[robot], (a, b)


def test_a_robot_alone_at_the_meeting_goal_searches_for_the_team():
    # A greedy teammate sits at the corner goal; the third-order robot goes to the goal of
    # the common view (the centre), waits alone, then searches, sees the teammate settled
    # and joins it. Without the search it would wait at the centre forever.
    s = Scenario(
        "rendezvous",
        [[20.0, 10.0], [4.0, 24.0]],
        [[15.0, 15.0], [3.0, 27.0]],
        ["range", "range"],
        sensing_range=5.0,
        events=[library_event("settle")],
        max_steps=150,
    )
    trial = simulate(s, "rules-third", seed=0, policies={1: "zero"})
    assert trial.success
    assert any(e[1] == "settle" and e[2] == 1 and 0 in e[4] for e in trial.events)
    patient = ActiveInference(3, search=False)
    assert not simulate(s, patient, seed=0, policies={1: "zero"}).success


def test_the_shared_ablation_models_teammates_over_the_robots_own_set(monkeypatch):
    # Robot 0 alone sees robot 2 settle: with nested sets it models robot 1 over the
    # larger set (robot 1 did not see it); "rules-third-shared" models it over its own set.
    from epistemica.aif.controller import Controller

    seen = []
    decide = Controller.decide

    def spy(self, robot, poses, prior=None, modelled_priors=None, **kw):
        seen.append((prior, modelled_priors))
        return decide(self, robot, poses, prior=prior, modelled_priors=modelled_priors, **kw)

    monkeypatch.setattr(Controller, "decide", spy)
    s = Scenario.paper("allocation", 3, 3, seed=2)
    s = s.replace(told=[((True, False, False), parse_formula("assigned(r3, g2)"))])
    for level, same in (("rules-third", False), ("rules-third-shared", True)):
        seen.clear()
        simulate(s.replace(max_steps=1), level, seed=2)
        prior, modelled = seen[0]
        assert modelled is not None
        assert all(np.array_equal(prior, m) for m in modelled) == same, level


def test_the_shared_ablation_changes_nothing_when_everyone_saw_everything():
    base = Scenario.paper("allocation", 3, 3, seed=4)
    told = base.replace(told=[((True,) * 3, parse_formula("~assigned(r1, g1)"))])
    nested, shared = (
        simulate(told, "rules-third", seed=4),
        simulate(told, "rules-third-shared", seed=4),
    )
    assert np.array_equal(nested.trajectory, shared.trajectory)


def test_a_group_waiting_for_the_rest_of_the_team_searches_for_it():
    # Robots 0 and 1 meet at the near goal and see each other; the greedy robot 2 sits at
    # the far goal, out of range. Neither robot is alone, yet each knows the team is not
    # together and nobody in sight is coming: they search, see robot 2 settled at a goal
    # where no one stood when they left, and join it. Without the search they wait forever.
    s = Scenario(
        "rendezvous",
        [[4.0, 4.0], [6.0, 5.0], [25.0, 24.0]],
        [[5.0, 5.0], [25.0, 25.0]],
        ["range", "range", "range"],
        sensing_range=8.0,
        events=[library_event("settle")],
        max_steps=150,
    )
    trial = simulate(s, "rules-third", seed=0, policies={2: "zero"})
    assert trial.success
    assert any(e[1] == "settle" and e[2] == 2 and {0, 1} & set(e[4]) for e in trial.events)
    patient = ActiveInference(3, search=False)
    assert not simulate(s, patient, seed=0, policies={2: "zero"}).success


def _common_view_switches(k: int, sight: str) -> str:
    """The common-view switch of robot 0 ("C" common, "o" own view) over a sight pattern
    ("+": it sees its teammate this step, "-": it does not)."""
    from types import SimpleNamespace

    s = Scenario("rendezvous", [[3.0, 3.0], [9.0, 3.0]], [[5.0, 5.0]], ["range"] * 2)
    policy = ActiveInference(3, sight_hysteresis=k, remember_sight=False)  # "C": the centre
    policy.start(s, [0, 1], [np.random.default_rng(0)] * 2)
    poses = np.broadcast_to(s.starts, (2, 2, 3)).copy()
    out = ""
    for step, mark in enumerate(sight):
        seen = np.array([[True, mark == "+"], [mark == "+", True]])
        observations = SimpleNamespace(step=step, poses=poses, seen=seen)
        policy.common_view.follow(observations, [0, 1])
        policy.common_view.follow(observations, [0, 1])  # a second call in a step changes nothing
        view = policy.common_view.views(observations, [0])[0]
        out += "C" if np.allclose(view[:, :2], s.workspace / 2) else "o"
    return out


def test_the_common_view_follows_sight_at_once_without_hysteresis():
    assert _common_view_switches(1, "++-+-+--++") == "ooCoCoCCoo"


def test_the_common_view_switches_only_after_k_steps_of_changed_sight():
    # at the edge of sight (seen every other step) the switch holds; it follows a change
    # only once the change has lasted k = 3 steps, in either direction
    assert _common_view_switches(3, "++-+-+---++-+++") == "ooooooooCCCCCCo"
    assert _common_view_switches(3, "--+-++---") == "CCCCCCCCC"


def _blind_views(starts, sight: str, remember: bool = True) -> list:
    """Robot 0's team view at each step of a sight pattern ("+": it sees every teammate,
    "-": not), the robots moving 1 m east each step, sensing range 10 m: ``"C"`` for
    the centre, the step whose estimates it uses, or ``"o"`` for its own view now."""
    from types import SimpleNamespace

    n = len(starts)
    s = Scenario("rendezvous", starts, [[5.0, 5.0]], ["range"] * n).replace(sensing_range=10.0)
    policy = ActiveInference(3, remember_sight=remember)
    policy.start(s, list(range(n)), [np.random.default_rng(0)] * n)
    out = []
    for step, mark in enumerate(sight):
        poses = np.broadcast_to(s.starts + np.array([step, 0.0, 0.0]), (n, n, 3)).copy()
        seen = np.full((n, n), mark == "+") | np.eye(n, dtype=bool)
        policy.common_view.follow(SimpleNamespace(step=step, poses=poses, seen=seen), range(n))
        view = policy.common_view.views(SimpleNamespace(poses=poses), [0])[0]
        if np.allclose(view, poses[0]):
            out.append("o")
        elif np.allclose(view[:, :2], s.workspace / 2):
            out.append("C")
        else:
            out.append(int(view[0, 0] - s.starts[0, 0]))  # the step it was taken at
    return out


def test_out_of_sight_the_common_view_is_the_last_whole_team_in_sight():
    # two robots 6 m apart: in sight at steps 0-2, then not: the view of step 2 stays
    assert _blind_views([[3.0, 3.0], [9.0, 3.0]], "+++--+-") == ["o", "o", "o", 2, 2, "o", 5]
    # without the memory, the centre (the ablation)
    assert _blind_views([[3.0, 3.0], [9.0, 3.0]], "++--", remember=False) == ["o", "o", "C", "C"]
    # robot 0 sees both teammates, but they are 16 m apart: the team was never all in
    # sight of each other, so nothing is remembered
    assert _blind_views([[10.0, 3.0], [18.0, 3.0], [2.0, 3.0]], "++--") == ["o", "o", "C", "C"]


def test_remembered_sight_ends_the_turn_back_at_the_edge_of_sight():
    # allocation_radius_2 seed 5: the robots' goals lead out of each other's sight; on
    # the centre view the shared order picks the other assignment, so both turned back
    # at the edge every step for 100 steps. Remembering the last step in sight, they go on.
    mission = load_mission("specs/stress/allocation_radius_2.epi")
    scenario = mission.scenario(5)
    centre = mission.parameters.replace(remember_sight=False)  # the ablation
    flipping = simulate(scenario, make_policy("convention+rules", centre), seed=5)
    assert not flipping.success
    switches = (np.diff(flipping.focal[:, 0, 0]) != 0).sum()
    assert switches >= 90
    policy = make_policy("convention+rules", mission.parameters)  # remembers by default
    steady = simulate(scenario, policy, seed=5)
    assert steady.success and (np.diff(steady.focal[:, 0, 0]) != 0).sum() <= 1
