"""The rendezvous search: who leaves a goal to look for the rest of the team, who comes back
to a teammate that never leaves (an anchor), and the sightings of settles it relies on."""

import numpy as np
import pytest

from epistemica.mission import parse_mission
from epistemica.sim import simulate
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.policy import FunctionPolicy

# r1 stands at g1 for good; r2 waits there with it; r3 waits at g2, 28 m away, out of
# sight. Only a search brings r3 over; r2 leaving r1 to search as well is wasted.
ANCHOR = """\
mission rendezvous
workspace 30
robot r1: range at (5, 5)
robot r2: range at (6, 5)
robot r3: range at (25, 25)
goal g1 at (5, 5)
goal g2 at (25, 25)
knows r1, r2: g1
knows r3: g2
sensing model paper noise 0.5 range 10
event settle seen by nearby
teammate r1 follows stationary
simulate trials 1 seed 0 steps 150 levels rules_third
"""


def _run(text: str, seed: int = 0, **changes):
    mission = parse_mission(text)
    parameters = mission.parameters.replace(**changes) if changes else mission.parameters
    return mission, simulate(
        mission.scenario(seed),
        "rules-third",
        seed=seed,
        policies=mission.policies(seed),
        parameters=parameters,
    )


def _distance_from(trial, robot: int, point) -> np.ndarray:
    return np.hypot(*(trial.trajectory[:, robot, :2] - np.asarray(point)).T)


def test_a_searcher_comes_back_to_a_teammate_that_never_leaves():
    _, trial = _run(ANCHOR)
    assert trial.policies[0] == "stationary"
    r2 = _distance_from(trial, 1, (5, 5))
    # r2 leaves after its wait, sees r1 still settling there, and is back for good: it
    # never gets further than the few steps it took before turning round.
    assert 1.0 < r2.max() < 6.0
    assert trial.success  # r3's search found them
    _, ablated = _run(ANCHOR, anchor_check=0)
    assert _distance_from(ablated, 1, (5, 5)).max() > 10.0  # r2 leaves r1 to search
    assert trial.steps < ablated.steps


def test_a_teammate_that_only_left_later_is_no_anchor():
    mission = parse_mission(ANCHOR.replace("teammate r1 follows stationary\n", ""))
    leave_at = 14

    def late_leaver(robot, observations, scenario):  # r1: at g1, then off east for good
        if observations.step < leave_at:
            return 0.0, 0.0
        heading = observations.poses[robot, robot, 2]
        return 1.0, float(np.angle(np.exp(-1j * heading)))

    trial = simulate(
        mission.scenario(0), "rules-third", seed=0, policies={0: FunctionPolicy(late_leaver)}
    )
    r2 = _distance_from(trial, 1, (5, 5))
    left = int(np.flatnonzero(r2 > 1.5)[0])
    assert left + 4 < leave_at  # r2 left first (r3 cannot know of g1: a short wait)
    assert r2[left + 2 : leave_at].min() < 0.5  # came back to r1, still settling there
    assert r2[leave_at:].max() > 10.0  # r1 gone, it searches on


def test_settles_are_seen_every_step_news_or_not():
    mission = parse_mission(ANCHOR)
    seen = []

    def record(robot, observations, scenario):
        if robot == 1:
            seen.append(observations.settles.copy())
        return 0.0, 0.0

    simulate(mission.scenario(0), FunctionPolicy(record), seed=0)
    settles = np.array(seen[2:20])
    # Everyone stands still: r2 sees r1 (1 m away) settle at g1 at every step, and r1
    # sees r2; nobody near g2 is in sight of r3, who stands alone at g2.
    assert (settles[:, 1, 0] == 0).all() and (settles[:, 0, 1] == 0).all()
    assert (settles[:, 2, :2] == -1).all() and (settles[:, :2, 2] == -1).all()
    assert (settles[:, 2, 2] == 1).all()  # an observer of its own settle


def test_without_events_there_are_no_settle_sightings():
    text = ANCHOR.replace("event settle seen by nearby\n", "")
    seen = []

    def record(robot, observations, scenario):
        seen.append(observations.settles)
        return 0.0, 0.0

    simulate(parse_mission(text).scenario(0), FunctionPolicy(record), seed=0)
    assert all(s is None for s in seen)


@pytest.mark.parametrize("bad", [-1, 1.5, True, "2"])
def test_anchor_check_must_be_a_count(bad):
    with pytest.raises(ValueError, match="anchor_check must be an integer >= 0"):
        ActiveParameters(anchor_check=bad)


# r1 alone at g1; r2 far off at g2, out of sight. Whether r2 knows of g1 decides whether
# r1 can expect it.
UNAWARE = """\
mission rendezvous
workspace 30
robot r1: range at (5, 5)
robot r2: range at (25, 25)
goal g1 at (5, 5)
goal g2 at (25, 25)
knows r1: g1
knows r2: g2
sensing model paper noise 0.5 range 10
event settle seen by nearby
simulate trials 1 seed 0 steps 40 levels rules_third
"""


def _first_departure(text: str) -> int:
    _, trial = _run(text)
    away = np.flatnonzero(_distance_from(trial, 0, (5, 5)) > 1.0)
    return int(away[0])


def test_a_robot_that_knows_a_teammate_cannot_know_its_goal_searches_sooner():
    p = ActiveParameters()
    unaware = _first_departure(UNAWARE)  # r1 knows r2 has never heard of g1
    aware = _first_departure(UNAWARE.replace("knows r1: g1", "knows r1, r2: g1"))
    assert p.unaware_wait < unaware <= p.unaware_wait + 3
    assert p.lone_wait < aware <= p.lone_wait + 3


@pytest.mark.parametrize("level", ["rules-first", "rules-third-shared", "convention+rules"])
def test_knowing_what_a_teammate_does_not_know_is_for_the_nested_levels(level):
    mission = parse_mission(UNAWARE)  # r1 knows r2 never heard of g1; these levels do not
    trial = simulate(mission.scenario(0), level, seed=0, parameters=mission.parameters)
    away = np.flatnonzero(_distance_from(trial, 0, (5, 5)) > 1.0)
    assert ActiveParameters().lone_wait < away[0]
