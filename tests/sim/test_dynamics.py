"""Pluggable dynamics and sensors, disc robots and obstacles (sim/engine/dynamics.py and
obstacles.py)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif.motion import move
from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.mission import parse_mission
from epistemica.sim import FunctionPolicy, Scenario, simulate
from epistemica.sim.engine.dynamics import HonestSensor, PaperSensor, Unicycle
from epistemica.sim.engine.obstacles import inside, line_of_sight, polygon, resolve_contacts

WALL = [[10, 5], [20, 5], [20, 7], [10, 7]]


def _same(a, b) -> bool:
    return (
        np.array_equal(a.trajectory, b.trajectory)
        and np.array_equal(a.estimates, b.estimates)
        and a.events == b.events
        and a.success == b.success
    )


# -- protocols: the built-ins are the old behaviour, and other objects plug in -----------


@pytest.mark.parametrize("observation", ["paper", "honest"])
def test_the_builtin_objects_run_the_same_trial_as_the_names(observation):
    s = Scenario.paper("allocation", 3, seed=2, observation=observation, sensing_range=12.0)
    sensor = PaperSensor() if observation == "paper" else HonestSensor()
    named = simulate(s, "rules-third", seed=2)
    plugged = simulate(s.replace(observation=sensor, dynamics=Unicycle()), "rules-third", seed=2)
    assert _same(named, plugged)


def test_unicycle_is_the_motion_model_of_aif():
    rng = np.random.default_rng(0)
    poses = rng.uniform(-5, 5, (6, 3))
    controls = np.column_stack([rng.uniform(0, 1, 6), rng.uniform(-3, 3, 6)])
    assert np.array_equal(Unicycle().step(poses, controls, 0.5), move(poses, controls, 0.5))


def test_a_dynamics_of_ones_own_moves_the_robots():
    class Holonomic:  # moves along heading + change, and keeps its heading
        def step(self, poses, controls, dt):
            out = poses.copy()
            angle = poses[:, 2] + controls[:, 1]
            out[:, 0] += controls[:, 0] * dt * np.cos(angle)
            out[:, 1] += controls[:, 0] * dt * np.sin(angle)
            return out

    s = Scenario("rendezvous", [[0, 0]], [[0, 10]], ["range"], dynamics=Holonomic())
    north = FunctionPolicy(lambda r, obs, sc: (1.0, np.pi / 2), name="north")
    trial = simulate(s.replace(max_steps=3), north, seed=0)
    assert np.allclose(trial.trajectory[:, 0], [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]])


def test_a_sensor_of_ones_own_is_what_robots_perceive():
    class Exact:
        name = "exact"

        def measure(self, poses, estimates, noise, scenario):
            return np.broadcast_to(poses, (poses.shape[0], *poses.shape)).copy()

    s = Scenario.paper("rendezvous", 3, 3, seed=1, observation=Exact(), position_noise=9.0)
    trial = simulate(s, "convention", seed=1)
    truth = trial.trajectory[:-1, None, :, :2]  # where everyone was when robot i decided
    assert np.allclose(trial.estimates, np.broadcast_to(truth, trial.estimates.shape))


def test_objects_without_the_protocol_are_refused():
    with pytest.raises(InvalidArgumentError, match="dynamics must have a step"):
        Scenario("rendezvous", [[0, 0]], [[1, 1]], ["range"], dynamics=object())
    with pytest.raises(InvalidArgumentError, match="unknown observation model"):
        Scenario("rendezvous", [[0, 0]], [[1, 1]], ["range"], observation=object())


def test_without_contacts_the_old_trial_is_run():
    s = Scenario.paper("rendezvous", 3, 3, seed=3)
    # radius 0 and no obstacle: moves are resolved but nothing is in the way
    points = s.replace(robot_radius=0.0)
    assert _same(simulate(s, "rules-third", seed=3), simulate(points, "rules-third", seed=3))


# -- geometry, by hand --------------------------------------------------------------------


def test_point_in_polygon_and_sight_by_hand():
    square = polygon([[0, 0], [2, 0], [2, 2], [0, 2]])
    assert inside(np.array([[1.0, 1.0], [3.0, 1.0], [1.0, -0.1]]), square).tolist() == [
        True,
        False,
        False,
    ]
    points = np.array([[-1.0, 1.0], [3.0, 1.0], [1.0, 5.0]])  # the third sees over it
    sight = line_of_sight(points, (square,))
    assert sight.tolist() == [[True, False, True], [False, True, True], [True, True, True]]


def test_a_wall_stops_a_robot_at_its_side():
    wall = polygon(WALL)
    before = np.array([[15.0, 0.0, 0.0]])
    after = np.array([[15.0, 6.0, np.pi / 2]])
    out = resolve_contacts(before, after, np.array([0.5]), (wall,))
    assert out[0, 1] == pytest.approx(4.5, abs=1e-6)  # radius 0.5 below the wall at y = 5
    assert out[0, 2] == after[0, 2]  # the heading the dynamics gave


def test_two_discs_stop_at_contact():
    before = np.array([[0.0, 0.0, 0.0], [5.0, 0.0, 0.0]])
    after = np.array([[4.0, 0.0, 0.0], [5.0, 0.0, 0.0]])
    out = resolve_contacts(before, after, np.array([1.0, 1.5]), ())
    assert out[0, 0] == pytest.approx(2.5, abs=1e-6)


def test_a_disc_that_touches_a_teammate_slides_along_it():
    # Touching discs (radii 0.5, centres 1 m apart); the first drives 1 m at 45 degrees,
    # into the second. Its move towards the second, (0.707, 0), is dropped; the rest,
    # (0, 0.707), is kept: it slides up past its teammate instead of stopping.
    before = np.array([[0.0, 0.0, np.pi / 4], [1.0, 0.0, 0.0]])
    after = before.copy()
    after[0, :2] = [np.sqrt(0.5), np.sqrt(0.5)]
    out = resolve_contacts(before, after, np.array([0.5, 0.5]), ())
    assert out[0, :2] == pytest.approx([0.0, np.sqrt(0.5)], abs=1e-6)
    # Head on there is nothing to slide along: it stays.
    after[0, :2] = [0.5, 0.0]
    assert resolve_contacts(before, after, np.array([0.5, 0.5]), ())[0, :2] == pytest.approx(
        [0.0, 0.0], abs=1e-6
    )


def test_two_grazing_discs_on_the_way_to_one_goal_do_not_lock():
    # A generated rendezvous (asymmetry family, tuning mission 74) had two 0.3 m discs
    # 0.58 m apart, each heading for the goal past the other: each move came closer to the
    # other first, so each was cut to nothing, every step to the limit.
    before = np.array([[20.9, 17.4, 0.95], [21.4, 17.1, 1.23]])
    after = before.copy()
    after[:, :2] += np.column_stack([np.cos(before[:, 2]), np.sin(before[:, 2])])
    out = resolve_contacts(before, after, np.array([0.3, 0.3]), ())
    moved = np.hypot(*(out[:, :2] - before[:, :2]).T)
    assert np.all(moved > 0.5)  # most of each 1 m step is kept
    assert np.hypot(*(out[0, :2] - out[1, :2])) >= np.hypot(*(before[0, :2] - before[1, :2]))


# -- properties: nobody enters an obstacle, discs never overlap ---------------------------

_moves = st.lists(st.tuples(st.floats(0, 1.5), st.floats(-np.pi, np.pi)), min_size=3, max_size=3)


@settings(max_examples=60, deadline=None)
@given(
    steps=st.lists(_moves, min_size=1, max_size=12),
    radius=st.floats(0.0, 1.0),
    seed=st.integers(0, 10_000),
)
def test_no_robot_enters_an_obstacle_or_a_teammate(steps, radius, seed):
    rng = np.random.default_rng(seed)
    wall = polygon(WALL)
    poses = np.column_stack([rng.uniform(0, 30, 3), rng.uniform(8, 30, 3), np.zeros(3)])
    radii = np.full(3, radius)
    start_gap = np.hypot(*(poses[:, None, :2] - poses[None, :, :2]).transpose(2, 0, 1))
    for controls in steps:
        moved = move(poses, np.array(controls), 1.0)
        poses = resolve_contacts(poses, moved, radii, (wall,))
        assert not inside(poses[:, :2], wall).any()
        gap = np.hypot(*(poses[:, None, :2] - poses[None, :, :2]).transpose(2, 0, 1))
        allowed = np.minimum(2 * radius, start_gap) - 1e-9
        off = ~np.eye(3, dtype=bool)
        assert np.all(gap[off] >= allowed[off])
        start_gap = np.minimum(start_gap, np.maximum(gap, 2 * radius))


def test_disc_robots_of_a_trial_never_overlap():
    s = Scenario.paper("rendezvous", 4, 2, seed=5, robot_radius=0.6)
    trial = simulate(s, "convention", seed=5)
    xy = trial.trajectory[:, :, :2]
    gaps = np.hypot(*(xy[:, :, None] - xy[:, None, :]).transpose(3, 0, 1, 2))
    first = gaps[0] + np.eye(4) * 99
    for t in range(gaps.shape[0]):
        off = gaps[t] + np.eye(4) * 99
        assert np.all(off >= np.minimum(1.2, first) - 1e-9)


def test_an_obstacle_hides_goals():
    s = Scenario(
        "allocation",
        [[15, 2], [3, 3]],
        [[15, 9], [25, 25]],
        ["range", "range"],
        known_goals=np.array([[False, True], [False, True]]),
        discovery_range=10.0,
        obstacles=[WALL],
        max_steps=1,
    )
    still = FunctionPolicy(lambda r, o, sc: (0.0, 0.0))
    # robot 0 is 7 m from goal 0, within the discovery range, but the wall is between
    assert not simulate(s, still, seed=0).knowledge.knows_goals((0,))[0]
    assert simulate(s.replace(obstacles=()), still, seed=0).knowledge.knows_goals((0,))[0]


def test_an_obstacle_hides_teammates():
    s = Scenario(
        "rendezvous",
        [[15, 2], [15, 12]],
        [[2, 28]],
        ["range", "range"],
        obstacles=[WALL],
        max_steps=1,
    )
    trial = simulate(s, FunctionPolicy(lambda r, o, sc: (0.0, 0.0)), seed=0)
    # never seen: each keeps the default estimate (the workspace centre) of the other
    assert np.allclose(trial.estimates[0, 0, 1], [15, 15])
    assert np.allclose(trial.estimates[0, 1, 0], [15, 15])
    open_field = simulate(s.replace(obstacles=()), FunctionPolicy(lambda r, o, sc: (0, 0)), seed=0)
    assert not np.allclose(open_field.estimates[0, 0, 1], [15, 15])


# -- bad values --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"obstacles": [[[0, 0], [1, 1], [2, 2]]]}, "has no area"),
        ({"obstacles": [[[0, 0], [1, 1]]]}, "at least 3"),
        ({"obstacles": [[[0, 0], [5, 0], [5, 5], [0, 5]]]}, "robot 0 starts"),
        ({"obstacles": [[[8, 8], [12, 8], [12, 12], [8, 12]]]}, "goal 0"),
        ({"robot_radius": -1.0}, "robot_radius"),
        ({"robot_radius": float("nan")}, "robot_radius"),
    ],
)
def test_bad_contact_values_are_refused(changes, message):
    with pytest.raises(InvalidArgumentError, match=message):
        Scenario("rendezvous", [[1, 1]], [[10, 10]], ["range"], **changes)


MISSION = """mission rendezvous
robot r1: range at (2, 15) radius 0.5
robot r2: range at (28, 15)
goal g1 at (15, 15)
obstacle (10, 5) (20, 5) (20, 7) (10, 7)
"""


def test_a_mission_file_selects_discs_and_obstacles():
    s = parse_mission(MISSION).scenario(0)
    assert s.robot_radius.tolist() == [0.5, 0.0]
    assert len(s.obstacles) == 1 and s.obstacles[0].tolist() == WALL
    assert parse_mission(MISSION.replace(" radius 0.5", "")).scenario(0).robot_radius is None


@pytest.mark.parametrize(
    ("old", "new", "where", "message"),
    [
        ("radius 0.5", "radius -2", (2, 35), "outside"),
        ("(20, 7) (10, 7)", "(30, 5)", (5, 1), "no area"),
        ("(10, 5) (20, 5) (20, 7) (10, 7)", "(10, 10) (20, 10) (20, 20) (10, 20)", (5, 1), "g1"),
        ("(10, 5) (20, 5) (20, 7) (10, 7)", "(1, 10) (3, 10) (3, 20) (1, 20)", (5, 1), "r1"),
    ],
)
def test_bad_mission_values_are_located(old, new, where, message):
    with pytest.raises(SpecError, match=message) as caught:
        parse_mission(MISSION.replace(old, new)).scenario(0)
    assert (caught.value.line, caught.value.column) == where
