"""An anchor outranks a find (``plan_anchor``, ``RendezvousSearch(hold=True)``): a searcher
that sees a member of the group it left still settled at that goal goes back to it, even
when it also sees teammates settled elsewhere."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.del_.errors import EpistemicaError
from epistemica.mission import parse_mission
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.search import RendezvousSearch

# r1 has left g1 to search; r2 (its group: a teammate that never leaves) still stands at
# g1; r3 stands settled at g2, 8 m from r1, in sight.
THREE = """\
mission rendezvous
workspace 30
robot r1: range at (5, 8)
robot r2: range at (5, 5)
robot r3: range at (13, 8)
goal g1 at (5, 5)
goal g2 at (13, 8)
sensing model paper noise 0.5 range 10
event settle seen by nearby
"""


class _Settled:
    """The settles robot r1 has seen (newest first): r3 at g2, r2 at g1."""

    def settled(self, chain):
        return [(2, 1), (1, 0)] if tuple(chain) == (0,) else []


def _step(hold: bool, since: int, r2_settles: bool = True):
    """One search step of r1, ``since + 1`` steps after it left g1 with r2."""
    scenario = parse_mission(THREE).scenario(0)
    search = RendezvousSearch(scenario, 10.0, 15, 0.8, 2, hold=hold)
    search.left[0], search.group[0, 1], search.since[0] = 0, True, since
    search.last[0] = (5.0, 8.0)
    poses = np.zeros((3, 3, 3))
    poses[:, :, :2] = [(5.0, 8.0), (5.0, 5.0), (13.0, 8.0)]
    settles = np.full((3, 3), -1)
    settles[0, 2] = 1
    if r2_settles:
        settles[0, 1] = 0
    seen, last = np.ones((3, 3), dtype=bool), np.full((3, 3), 9)
    known = np.ones((3, 2), dtype=bool)
    observations = Observations(9, poses, seen, last, known, ~known, _Settled(), settles)
    searching = search.searchers(observations, np.array([0]))
    return search, searching[0]


def test_without_hold_a_teammate_settled_elsewhere_ends_the_search():
    search, searching = _step(False, since=1)
    # r3 settled at g2, outside the group r1 left: found. The search ends (left -1) and
    # r1 never waits with r2, although r2 is still at g1 two steps after r1 left.
    assert not searching
    assert search.left[0] == -1 and search.anchor[0] == -1


def test_with_hold_the_anchor_outranks_the_find():
    search, searching = _step(True, since=1)
    # Two steps after leaving (anchor_check = 2), r2 still settles at g1: r1 goes back to
    # wait with it (anchor g1, with r2), r3's settle at g2 notwithstanding.
    assert searching
    assert search.anchor[0] == 0 and search.anchors[0].tolist() == [False, True, False]
    assert search.meeting[0] == -1 and search.leader[0] == -1


@pytest.mark.parametrize(
    ("since", "r2_settles"),
    [(0, True), (15, True), (1, False)],  # too early, too late, r2 not seen at g1
)
def test_hold_needs_an_anchor_seen_in_time(since, r2_settles):
    search, searching = _step(True, since=since, r2_settles=r2_settles)
    # One step after leaving the group may still be leaving; after lone_wait (15) steps
    # r2 is not an anchor either; nor is a member not seen settling there. The find wins.
    assert not searching and search.anchor[0] == -1


def test_plan_anchor_is_a_switch_and_on_by_default():
    assert ActiveParameters().plan_anchor is True
    with pytest.raises(EpistemicaError, match="plan_anchor must be true or false"):
        ActiveParameters(plan_anchor=1)
