"""Joining teammates settled at a goal the robot does not know (``plan_join``,
:class:`~epistemica.sim.policies.joining.Joining`): counted, compared by group size, off
where it does not apply, and, end to end, the split team of tuning mission asymmetry 97
in small."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.mission import parse_mission
from epistemica.sim import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.joining import Joining
from epistemica.sim.policies.parameters import ActiveParameters


def _scene(n: int = 4, kind: str = "rendezvous", goals: int = 2) -> Scenario:
    return Scenario.paper(kind, n, goals, seed=0)


def _observe(scenario, step, at_goal, known, settles, poses=None) -> Observations:
    """Every robot stands exactly on its goal in ``at_goal`` and sees all the others."""
    n = scenario.n_robots
    if poses is None:
        poses = np.zeros((n, n, 3))
        poses[:, :, :2] = scenario.goals[at_goal][None]
    seen = np.ones((n, n), dtype=bool)
    known = np.asarray(known, dtype=bool)
    return Observations(step, poses, seen, np.full((n, n), step), known, np.zeros_like(known),
                        None, np.asarray(settles))  # fmt: skip


def test_outnumbered_robot_waits_patience_steps_then_heads_where_they_stand():
    s = _scene(3)
    join = Joining(s, patience=2)
    # r1 stands on g1 and knows only it; r2, r3 stand settled on g2, which r1 does not know.
    known = [[True, False], [True, True], [True, True]]
    settles = [[-1, 1, 1], [0, -1, 1], [0, 1, -1]]
    poses = np.zeros((3, 3, 3))
    poses[:, 0, :2] = s.goals[0]
    # Where r1 sees r2 and r3 (noisy sightings about g2): it heads for their mean.
    poses[0, 1, :2] = s.goals[1] + [1.0, 0.0]
    poses[0, 2, :2] = s.goals[1] + [0.0, -3.0]
    out = [join.target(_observe(s, k, [0, 1, 1], known, settles, poses), 0) for k in range(4)]
    # Step 0: not yet seen to stand still; steps 1, 2: counted 1, 2 (patience 2); 2, 3: goes.
    assert [o is None for o in out] == [True, True, False, False]
    assert np.allclose(out[2], s.goals[1] + [0.5, -1.5])
    assert join.goal[0] == 1


def test_the_goal_found_hands_the_robot_back_to_its_plan():
    s = _scene(3)
    join = Joining(s, patience=1)
    settles = [[-1, 1, 1], [0, -1, 1], [0, 1, -1]]
    known = [[True, False], [True, True], [True, True]]
    for k in range(2):
        join.target(_observe(s, k, [0, 1, 1], known, settles), 0)
    assert join.goal[0] == 1
    known[0][1] = True  # discovered on the way
    assert join.target(_observe(s, 2, [0, 1, 1], known, settles), 0) is None
    assert join.goal[0] == -1


def test_groups_of_equal_size_the_one_with_the_lowest_numbered_robot_stays():
    s = _scene(4)
    # r1, r2 on g1 (known to them only); r3, r4 on g2 (known to them only).
    known = [[True, False], [True, False], [False, True], [False, True]]
    settles = [[-1, 0, 1, 1], [0, -1, 1, 1], [0, 0, -1, 1], [0, 0, 1, -1]]
    join = Joining(s, patience=1)
    for k in range(3):
        going = [join.target(_observe(s, k, [0, 0, 1, 1], known, settles), r) is not None
                 for r in range(4)]  # fmt: skip
    assert going == [False, False, True, True]


def test_a_larger_group_with_the_robot_stays():
    s = _scene(4)
    # r1, r2, r3 on g1; r4 alone on g2, unknown to r1: r1 waits with its group.
    known = [[True, False], [True, True], [True, True], [True, True]]
    settles = [[-1, 0, 0, 1], [0, -1, 0, 1], [0, 0, -1, 1], [0, 0, 0, -1]]
    join = Joining(s, patience=1)
    out = [join.target(_observe(s, k, [0, 0, 0, 1], known, settles), 0) for k in range(4)]
    assert out == [None] * 4


@pytest.mark.parametrize(("kind", "patience"), [("allocation", 1), ("rendezvous", 0)])
def test_nothing_off_rendezvous_or_when_off(kind, patience):
    s = _scene(3, kind, goals=3)  # an allocation of three needs three goals
    join = Joining(s, patience=patience)
    known = [[True, False, True], [True, True, True], [True, True, True]]
    settles = [[-1, 1, 1], [0, -1, 1], [0, 1, -1]]
    out = [join.target(_observe(s, k, [0, 1, 1], known, settles), 0) for k in range(4)]
    assert out == [None] * 4


SPLIT = """mission rendezvous
workspace 20
robot r1: range at (3, 4)
robot r2: range at (16, 16)
robot r3: range at (16, 17.5)
goal g1 at (3, 3)
goal g2 at (16, 17)
obstacle (8, 8) (12, 8) (12, 12) (8, 12)
sensing model paper noise 0.1 discovery 3
knows r1: g1
knows r2: g2
knows r3: g2
event settle seen by nearby
"""


@pytest.mark.parametrize(("join", "success"), [(0, False), (3, True)])
def test_a_split_team_behind_a_wall_meets_only_by_joining(join, success):
    # r1 knows only g1, r2 and r3 only g2; the wall hides each group from the other, so
    # the sighting of a settle never teaches the goal (asymmetry 97 in small). r1 sees
    # both settle at g2 (the event's observers); with plan_join it goes there.
    mission = parse_mission(SPLIT + f"policy plan_join {join}\n", "split.epi")
    trial = mission.trial(40, 0, "third")
    assert trial.success is success


def test_on_by_default_and_a_count():
    assert ActiveParameters().plan_join == 3
    with pytest.raises(ValueError, match="plan_join must be an integer >= 0"):
        ActiveParameters(plan_join=-1)
