"""The planning stage: the draws that stand for a teammate never seen, and the teammate
types read from their moves."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from epistemica.aif.planning import Planner
from epistemica.aif.teammates import TYPES
from epistemica.del_.errors import EpistemicaError
from epistemica.mission import parse_mission
from epistemica.sim import Scenario, simulate
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.levels import make_policy
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage, recording_plans, sighting_variance


def _observations(step: int, teammate, last_seen) -> Observations:
    poses = np.zeros((2, 2, 3))
    poses[0, 0, :2] = [5.0, 5.0]
    poses[0, 1, :2] = teammate
    seen = np.array([[True, last_seen == step], [True, True]])
    last = np.array([[step, last_seen], [step, step]])
    known = np.ones((2, 2), dtype=bool)
    return Observations(step, poses, seen, last, known, ~known)


def test_only_never_seen_teammates_get_draws():
    scenario = Scenario.paper("rendezvous", 2, 2, seed=3)
    stage = PlanningStage(scenario, ActiveParameters(planning=True, plan_unseen=5), order=2)
    places = stage.unseen(_observations(4, [15.0, 15.0], -1), 0)
    assert places.shape == (5, 2, 2)
    assert np.isnan(places[:, 0]).all() and not np.isnan(places[:, 1]).any()
    assert ((places[:, 1] >= 0) & (places[:, 1] <= scenario.workspace)).all()
    assert stage.unseen(_observations(4, [15.0, 15.0], 2), 0) is None
    off = PlanningStage(scenario, ActiveParameters(planning=True, plan_unseen=0), order=2)
    assert off.unseen(_observations(4, [15.0, 15.0], -1), 0) is None


def test_plan_types_is_checked_and_zero_turns_the_types_off():
    with pytest.raises(EpistemicaError):
        ActiveParameters(plan_types=1.0)
    scenario = Scenario.paper("rendezvous", 2, 2, seed=3)
    off = PlanningStage(scenario, ActiveParameters(planning=True, plan_types=0.0), order=2)
    ctrl = SimpleNamespace(goals=scenario.goals, configurations=np.array([[0, 0], [1, 1]]))
    assert off.typed(ctrl, np.arange(2), 0, _observations(4, [15.0, 15.0], 4)) is None


def _stationary_trial(plan_types: float):
    """Design seed 1004 of the 5-robot stress cell where one silent teammate stops on a
    random goal (the planner without types waited for it elsewhere). The 3-robot cell's
    seed 1004 was used before the planner read sightings against their stated noise
    (``plan_noise``); with it, that cell no longer needs the types."""
    path = (
        Path(__file__).resolve().parents[2]
        / "specs/stress/rendezvous_adhoc_stationary_silent_5.epi"
    )
    text = path.read_text() + f"\npolicy plan_types {plan_types}\n"
    mission = parse_mission(text, str(path))
    return mission, mission.trial(100, 1004, "third")


def test_the_team_meets_a_stationary_teammate_on_its_goal_once_its_type_is_read():
    mission, trial = _stationary_trial(0.97)
    (stationary,) = mission.policies(1004)
    assert trial.success
    final = trial.trajectory[-1, :, :2]
    goals = mission.scenario(1004).goals
    # Everyone ends at the goal the stationary teammate stands on.
    nearest = np.argmin(np.hypot(*(final[:, None, :] - goals[None]).transpose(2, 0, 1)), axis=1)
    assert (nearest == nearest[stationary]).all()
    _, without = _stationary_trial(0.0)
    assert not without.success  # predicted as a planner, it was waited for elsewhere


def test_recorded_plans_carry_the_type_posteriors_that_typed_a_teammate():
    with recording_plans() as plans:
        mission, _ = _stationary_trial(0.97)
    (stationary,) = mission.policies(1004)
    assert plans and all(np.allclose(p.types.sum(axis=1), 1.0) for p in plans)
    typed = [p for p in plans if p.typed.any()]
    assert typed and all(p.typed[stationary] for p in typed)  # only the stationary one
    greedy, still = TYPES.index("greedy"), TYPES.index("stationary")
    for p in typed:  # typed only once greedy + stationary reach the threshold
        assert p.types[p.typed][:, [greedy, still]].sum(axis=1).min() >= 0.97 - 1e-9
    with recording_plans() as plans:
        _stationary_trial(0.0)
    assert plans and all(p.types is None and p.typed is None for p in plans)


def test_sighting_variance_of_each_sensor_by_hand():
    paper = Scenario.paper("rendezvous", 2, 2, seed=3).replace(position_noise=2.0)
    assert sighting_variance(paper, [0.0, 7.0]).tolist() == [2.0, 2.0]
    honest = paper.replace(observation="honest", position_noise=8.0, angle_noise=0.1)
    # the range's 8 m^2 and the bearing's (10 m)^2 * 0.1 rad^2, averaged over two axes
    assert sighting_variance(honest, [0.0, 10.0]).tolist() == pytest.approx([4.0, 9.0])


@pytest.mark.parametrize("noise", [0.0, 1.0])
def test_a_move_between_noisy_sightings_weighs_by_their_variance(noise):
    scenario = Scenario.paper("rendezvous", 2, 2, seed=3).replace(position_noise=2.0)
    params = ActiveParameters(planning=True, plan_noise=noise, plan_leak=0.0)
    stage = PlanningStage(scenario, params, order=2)
    stage.observe(_observations(4, [15.0, 15.0], 4), 0)
    stage.observe(_observations(5, [15.0, 15.0], 5), 0)  # stood still for one step
    read = stage._read[0][1]
    # Standing still misses each goal's step of min(v dt, d): residual^2 = reach^2.
    distance = np.hypot(*(scenario.goals - [15.0, 15.0]).T)
    reach = np.minimum(scenario.max_speed[1] * scenario.dt, distance)
    model = 0.5 * float(scenario.max_speed.mean()) * scenario.dt
    variance = model**2 + noise * 2 * 2.0
    assert read == pytest.approx(-(reach**2) / (2 * variance))


def test_progress_is_the_time_driven_towards_the_goal_since_choosing_it():
    scenario = Scenario.paper("rendezvous", 2, 2, seed=3)
    stage = PlanningStage(scenario, ActiveParameters(planning=True, plan_progress=1.0), order=2)
    goal = scenario.goals[1]
    start = goal + np.array([6.0, 8.0])  # 10 m away when chosen
    stage._start[0] = (1, 10.0)
    halfway = (start + goal) / 2  # 5 m driven
    assert stage._progress(0, halfway) == pytest.approx(5.0 / scenario.max_speed[0])
    assert stage._progress(0, start + np.array([3.0, 4.0])) == 0.0  # driven away: nothing to lose
    stage.forget(0)
    assert stage._progress(0, halfway) == 0.0


def _read_after_a_gap(resight: bool, first_seen: int) -> tuple[np.ndarray, Scenario]:
    """What robot 0 reads of robot 1: planned at steps 4, 5 and 6; robot 1 seen at
    ``first_seen`` (-1: never) at (10, 10), unseen at 5, seen at 6 at (12, 10)."""
    scenario = Scenario.paper("rendezvous", 2, 2, seed=3)
    # The sightings' noise is left out (``plan_noise=0``) so that sigma is the motion
    # model's alone; test_a_move_between_noisy_sightings_weighs_by_their_variance adds it.
    params = ActiveParameters(planning=True, plan_leak=0.0, plan_resight=resight, plan_noise=0.0)
    stage = PlanningStage(scenario, params, order=2)
    where = [10.0, 10.0] if first_seen >= 0 else [15.0, 15.0]  # a placeholder if never
    stage.observe(_observations(4, where, first_seen), 0)
    stage.observe(_observations(5, where, first_seen), 0)  # not seen: the estimate stays
    stage.observe(_observations(6, [12.0, 10.0], 6), 0)
    return stage._read[0][1], scenario


@pytest.mark.parametrize("resight", [False, True])
def test_a_move_is_read_between_two_sightings_over_their_gap(resight):
    read, scenario = _read_after_a_gap(resight, first_seen=4)
    steps = 2 if resight else 1  # seen at 4 and 6; the robot last planned at 5
    start, end = np.array([10.0, 10.0]), np.array([12.0, 10.0])
    to_goal = scenario.goals - start
    distance = np.hypot(*to_goal.T)
    reach = np.minimum(scenario.max_speed[1] * steps * scenario.dt, distance)
    residual = (end - start) - reach[:, None] * to_goal / distance[:, None]
    sigma = 0.5 * float(scenario.max_speed.mean()) * steps * scenario.dt
    assert read == pytest.approx(-(residual**2).sum(axis=1) / (2 * sigma**2))


def test_a_first_sighting_is_no_move_from_the_placeholder_with_resight():
    read, _ = _read_after_a_gap(True, first_seen=-1)
    assert (read == 0).all()
    read, _ = _read_after_a_gap(False, first_seen=-1)  # without: a move from (15, 15)
    assert (read < 0).all()
    with pytest.raises(EpistemicaError):
        ActiveParameters(plan_resight=1)


def _plan_inputs(monkeypatch, mission: str) -> list[tuple[np.ndarray, int | None]]:
    """The evidence and previous goal of every plan of a 25-step trial of ``third``."""
    seen, plan = [], Planner.plan

    def spy(self, robot, positions, prior=None, sets=None, moving=None, evidence=None,
            previous=None, *rest, **options):  # fmt: skip
        seen.append((np.array(evidence, dtype=float), previous))
        return plan(self, robot, positions, prior, sets, moving, evidence, previous, *rest,
                    **options)  # fmt: skip

    monkeypatch.setattr(Planner, "plan", spy)
    scenario = Scenario.paper(mission, 3, 6 if mission == "multitask" else 3, seed=2)
    simulate(scenario.replace(max_steps=25), make_policy("third"), seed=2)
    return seen


def test_multitask_plans_keep_no_goal_and_read_no_moves(monkeypatch):
    """The upper level re-chooses a multitask team's tasks every step: a plan there charges
    nothing for leaving the task it headed for and reads no teammate's moves; a goal
    mission's plans do both (so the check can fail)."""
    tasks = _plan_inputs(monkeypatch, "multitask")
    assert tasks and all(previous is None and not e.any() for e, previous in tasks)
    goals = _plan_inputs(monkeypatch, "rendezvous")
    assert any(previous is not None for _, previous in goals)
    assert any(e.any() for e, _ in goals)
