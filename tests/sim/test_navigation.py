"""Driving round known walls (sim/engine/navigation.py): the roadmap's geometry, worked by
hand, its laws, and the closed loop of a robot whose goal lies behind a wall."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.aif.planning import motion_evidence
from epistemica.del_.errors import EpistemicaError
from epistemica.mission import parse_mission
from epistemica.sim import FunctionPolicy, Scenario, simulate
from epistemica.sim.engine.navigation import Roadmap, clear
from epistemica.sim.engine.obstacles import inside, polygon

# A 2 m square block centred at (10, 10).
BLOCK = polygon([[9, 9], [11, 9], [11, 11], [9, 11]])


def test_the_corners_lie_a_margin_out_from_both_edges():
    roadmap = Roadmap((BLOCK,), margin=0.5, workspace=20.0)
    # A right angle's mitre: each corner moves 0.5 m out along both edges' normals.
    expected = {(8.5, 8.5), (11.5, 8.5), (11.5, 11.5), (8.5, 11.5)}
    assert {tuple(p) for p in roadmap.nodes.round(6).tolist()} == expected
    # Adjacent corners see each other (2 + 2 * 0.5 = 3 m apart); opposite ones do not,
    # and go round by a neighbour: 3 + 3 m.
    d = roadmap.distance
    assert np.allclose(sorted(d[0]), [0.0, 3.0, 3.0, 6.0])


def test_the_way_round_takes_the_shorter_side():
    roadmap = Roadmap((BLOCK,), margin=0.5, workspace=20.0)
    start, goal = np.array([5.0, 9.9]), np.array([15.0, 9.9])
    assert not clear(start, goal, (BLOCK,), 0.0)
    # 0.1 m below the centre line: by the lower corners (3.77 + 3 + 3.77 m against 3.85 +
    # 3 + 3.85 over the top). The far lower corner is hidden (the line to it enters the
    # block at x = 9, y = 9.04), so (8.5, 8.5) first.
    assert roadmap.waypoint(start, goal).tolist() == [8.5, 8.5]
    # From that corner the goal is hidden too (the line crosses y = 9 at x = 10.8): the
    # next corner, and from there the goal in sight.
    assert roadmap.waypoint(np.array([8.5, 8.5]), goal).tolist() == [11.5, 8.5]
    assert roadmap.waypoint(np.array([11.5, 8.5]), goal) is goal


def test_clear_lets_a_robot_pressed_against_a_wall_drive_off_it():
    pressed = np.array([8.0 - 1e-6, 10.0])  # touching the block's left edge, 1 m radius off
    assert clear(pressed, np.array([3.0, 10.0]), (BLOCK,), 0.0)  # away
    assert not clear(pressed, np.array([15.0, 10.0]), (BLOCK,), 1.0)  # through it
    # A segment passing 0.8 m from the block is clear for a point, not for a 1 m disc.
    low = np.array([5.0, 8.2]), np.array([15.0, 8.2])
    assert clear(*low, (BLOCK,), 0.0) and not clear(*low, (BLOCK,), 1.0)


def test_corners_outside_the_workspace_are_left_out():
    wall = polygon([[4, 0], [5, 0], [5, 8], [4, 8]])  # from the floor up
    roadmap = Roadmap((wall,), margin=0.5, workspace=10.0)
    assert sorted(roadmap.nodes.tolist()) == [[3.5, 8.5], [5.5, 8.5]]
    # A wall from floor to ceiling has no way round.
    full = polygon([[4, 0], [5, 0], [5, 10], [4, 10]])
    closed = Roadmap((full,), margin=0.5, workspace=10.0)
    assert closed.waypoint(np.array([2.0, 5.0]), np.array([8.0, 5.0])) is None


# Two blocks nearly touching at a corner, 0.3 m apart (generated allocation mission 22 of
# the tuning split): BLOCK's lower-left corner moved out by 0.5 m lands inside NEXT.
NEXT = polygon([[7.0, 7.0], [8.7, 7.0], [8.7, 8.8], [7.0, 8.8]])


def test_a_corner_moved_into_another_obstacle_is_left_out():
    roadmap = Roadmap((BLOCK, NEXT), margin=0.5, workspace=20.0)
    # BLOCK's (8.5, 8.5) lies in NEXT, NEXT's (9.2, 9.3) in BLOCK: 8 corners less those 2.
    corners = {tuple(p) for p in roadmap.nodes.round(6).tolist()}
    assert len(corners) == 6 and (8.5, 8.5) not in corners and (9.2, 9.3) not in corners
    for poly in (BLOCK, NEXT):
        assert not inside(roadmap.nodes, poly).any()


# The walls of generated allocation mission 22 (tuning split), 0.3 m apart at a corner.
NEAR_CORNERS = """\
mission rendezvous
workspace 22
robot r1: range at (10.0, 5.5)
goal g1 at (16.1, 9.7)
obstacle (11.8, 3.5) (13.6, 3.5) (13.6, 7.4) (11.8, 7.4)
obstacle (9.2, 7.2) (11.5, 7.2) (11.5, 13.1) (9.2, 13.1)
simulate trials 1 seed 0 steps 60 levels convention
"""


def test_a_robot_between_two_walls_near_a_corner_reaches_its_goal():
    # Before the fix the way round began at a corner inside the other wall: r1 drove
    # into the first wall (x = 11.8) and stood there to the step limit.
    trial = simulate(parse_mission(NEAR_CORNERS).scenario(0), "convention", seed=0)
    assert trial.success and trial.steps < 30


@settings(max_examples=80, deadline=None)
@given(
    x=st.floats(2.0, 8.0),
    y=st.floats(0.5, 19.5),
    gx=st.floats(12.0, 18.0),
    gy=st.floats(0.5, 19.5),
)
def test_a_waypoint_is_always_in_clear_reach(x, y, gx, gy):
    roadmap = Roadmap((BLOCK,), margin=0.5, workspace=20.0)
    start, goal = np.array([x, y]), np.array([gx, gy])
    point, here, length = roadmap.waypoint(start, goal), start, 0.0
    assert point is not None  # a block in open space always has a way round
    for _ in range(6):  # follow the waypoints: each in clear reach, ending at the goal
        assert clear(here, point, (BLOCK,), 0.0)
        length += np.hypot(*(point - here))
        if point is goal:
            break
        here, point = point, roadmap.waypoint(point, goal)
    assert point is goal
    assert length >= np.hypot(*(goal - start)) - 1e-9  # never shorter than straight


# r1 at the left of a wall that stands from the floor to 20 m; its goal straight across.
BEHIND = """\
mission rendezvous
workspace 30
robot r1: range at (5, 10)
goal g1 at (25, 10)
obstacle (14, 0) (16, 0) (16, 20) (14, 20)
simulate trials 1 seed 0 steps 80 levels convention
"""


@pytest.mark.parametrize("level", ["convention", "third", "rules-third", "third-priormode"])
def test_a_robot_drives_round_a_wall_to_a_goal_behind_it(level):
    scenario = parse_mission(BEHIND).scenario(0)
    routed = simulate(scenario, level, seed=0)
    straight = simulate(scenario, level, seed=0, navigate=False)
    wall = scenario.obstacles[0]
    # Straight: pressed against the wall (x = 14) to the step limit.
    assert not straight.success
    assert abs(straight.trajectory[-1, 0, 0] - 14.0) < 0.01
    # Round: over the wall's top (20.5 m) and down to the goal, never inside the wall.
    assert routed.success
    assert routed.trajectory[:, 0, 1].max() > 20.0
    assert not inside(routed.trajectory[:, 0, :2], wall).any()


def test_a_robot_that_waits_is_not_moved():
    scenario = parse_mission(BEHIND).scenario(0)

    def wait(robot, observations, scenario):
        return 0.0, 0.0

    trial = simulate(scenario, FunctionPolicy(wait), seed=0)
    assert np.allclose(trial.trajectory[:, 0, :2], [5.0, 10.0])


def test_without_obstacles_navigation_changes_nothing():
    scenario = Scenario.paper("rendezvous", 3, 3, seed=4)
    a = simulate(scenario, "third", seed=4)
    b = simulate(scenario, "third", seed=4, navigate=False)
    assert np.array_equal(a.trajectory, b.trajectory)


def test_navigate_must_be_a_switch():
    with pytest.raises(EpistemicaError, match="navigate must be true or false"):
        simulate(Scenario.paper("rendezvous", 2, 2, seed=0), "convention", navigate=1)


def test_a_teammate_driving_round_a_wall_is_read_as_heading_for_its_goal():
    roadmap = Roadmap((BLOCK,), margin=0.5, workspace=20.0)
    goals = np.array([[15.0, 9.9], [5.0, 2.0]])
    here = np.array([[5.0, 9.9]])
    aims = roadmap.aims(here, goals)
    # Behind the block, g1's aim is the first corner round it; g2 is in sight.
    assert aims[0, 0].tolist() == [8.5, 8.5] and aims[0, 1].tolist() == [5.0, 2.0]
    # A 1 m step towards that corner: no error for g1 when read against the aims, 0.38 m
    # of error (-0.29 nats at sigma 0.5) when read against the straight line to g1.
    step = here + (aims[0, 0] - here) / np.hypot(*(aims[0, 0] - here[0]))
    routed = motion_evidence(here, step, aims, [1.0], 1.0, 0.5)[0]
    straight = motion_evidence(here, step, goals, [1.0], 1.0, 0.5)[0]
    assert routed[0] == pytest.approx(0.0, abs=1e-12)
    unit = (goals[0] - here[0]) / np.hypot(*(goals[0] - here[0]))
    expected = -np.sum((step[0] - here[0] - unit) ** 2) / (2 * 0.5**2)
    assert straight[0] == pytest.approx(expected) and straight[0] < -0.28
    assert routed[1] == pytest.approx(straight[1])  # g2: the same straight line


def test_a_robot_with_a_clear_way_keeps_its_policys_control():
    # The goal on r1's side of the wall: the rules' controller's own moves, untouched.
    text = BEHIND.replace("goal g1 at (25, 10)", "goal g1 at (10, 14)")
    scenario = parse_mission(text).scenario(0)
    routed = simulate(scenario, "rules-third", seed=0)
    straight = simulate(scenario, "rules-third", seed=0, navigate=False)
    assert routed.success
    assert np.array_equal(routed.trajectory, straight.trajectory)
