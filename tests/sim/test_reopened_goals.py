"""Goals an event reopens: what a robot saw closed before and then saw (or was shown)
open again no longer binds it (the knowledge's withdrawn facts, the sensing's news)."""

from __future__ import annotations

import numpy as np

from epistemica.del_ import Observation
from epistemica.mission import parse_mission
from epistemica.sim import Scenario, simulate
from epistemica.sim.engine._streams import trial_streams
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.sensing import Sensing

# r1 starts 3 m from g3, which is closed: it sees it closed. At step 3 an event closes g2
# and reopens g3, shown to both robots. Two robots, two open goals left (g1, g3): r2,
# next to g1, takes it; r1 must take g3, the goal it once saw closed.
REOPENED = """\
mission allocation
workspace 20
robot r1: range at (15, 4)
robot r2: range at (4, 15)
goal g1 at (4, 18)
goal g2 at (10, 10)
goal g3 at (16, 1) closed
sensing model honest noise 0.2 discovery 5
event change {
    when step 3
    closes g2
    opens g3
    announces closed(g2)
    reveals g3
    full r1, r2
}
simulate trials 1 seed 0 steps 60 levels third
"""


def test_a_goal_seen_closed_and_reopened_by_an_event_is_taken():
    # Before the reopening voided what r1 saw, every level failed here: r1 knew g3
    # closed for good, found too few goals and swept the workspace to the step limit.
    mission = parse_mission(REOPENED, "reopened.epi")
    for level in ("third", "rules-third", "first", "convention"):
        trial = simulate(mission.scenario(0), level, seed=0, policies=mission.policies(0),
                         parameters=mission.parameters)  # fmt: skip
        assert trial.success, level
        ends = trial.trajectory[-1, :, :2]
        assert np.hypot(*(ends[0] - [16, 1])) <= 1.0 and np.hypot(*(ends[1] - [4, 18])) <= 1.0


def test_the_knowledge_drops_a_closing_its_chain_saw_withdrawn():
    k = TeamKnowledge(["r1", "r2"], ["g1", "g2", "g3"])
    both = np.array([True, True])
    assert k.notice_closed(1, both)
    assert k.knows_done((0,)).tolist() == [False, True, False]
    reopen = Observation("change", full={"r1"}, withdraws=(k.closed[1],))
    assert k.observe(reopen)
    assert k.knows_done((0,)).tolist() == [False, False, False]  # r1 saw it reopen
    assert k.knows_done((1,)).tolist() == [False, True, False]  # r2 did not
    assert k.knows_done((0, 1)).tolist() == [False, True, False]  # r1 knows r2 did not
    rows = np.array([[0, 1], [0, 2], [1, 2]])  # the rows using g2 (index 1) go with it
    assert k.possible((0,), rows).tolist() == [True, True, True]
    assert k.possible((1,), rows).tolist() == [False, True, False]
    assert k.notice_closed(1, np.array([True, False]))  # closed again: news for r1
    assert k.knows_done((0,)).tolist() == [False, True, False]
    assert k.notice_open(1, np.array([True, False]))  # and open again, seen
    assert k.knows_done((0,)).tolist() == [False, False, False]


def test_a_robot_near_a_goal_sees_it_open_again():
    s = Scenario("allocation", [[0, 0], [19, 19]], [[1, 0], [18, 19]], ["range"] * 2,
                 discovery_range=3.0)  # fmt: skip
    sensing = Sensing(s, trial_streams(0, 2).observation)
    poses = np.array(s.starts, dtype=float)
    closed = np.array([True, False])
    assert sensing.observe(poses, 0, closed=closed).known_done.tolist() == [
        [True, False],  # r1 is 1 m from g1
        [False, False],  # r2 is 26 m away
    ]
    assert not sensing.observe(poses, 1, closed=~closed).known_done[0, 0]  # reopened
    far = sensing.observe(poses, 2, closed=closed)  # closed again, r2 still far
    assert far.known_done.tolist() == [[True, False], [False, False]]
