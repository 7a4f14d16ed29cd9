"""Where a searcher looks (``plan_sighted``, ``RendezvousSearch(sighted=True)``): after the
goals where it saw missing teammates settle, and before the other goals it knows, where it
last saw a teammate it does not see now, the newest sighting first."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.del_.errors import EpistemicaError
from epistemica.mission import parse_mission
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.search import RendezvousSearch

# r1 searches from (5, 5); it knows g1 (5, 5, where it waited) and g2 (25, 5). It last saw
# r2 at (5, 25) at step 4 and r3 at (25, 25) at step 6; it sees neither now (step 9).
THREE = """\
mission rendezvous
workspace 30
robot r1: range at (5, 5)
robot r2: range at (5, 25)
robot r3: range at (25, 25)
goal g1 at (5, 5)
goal g2 at (25, 5)
sensing model paper noise 0.5 range 10
event settle seen by nearby
"""


class _Settled:
    """The settles r1 has seen, newest first (``clue``: r3 settled at g2)."""

    def __init__(self, clue: bool) -> None:
        self.clue = clue

    def settled(self, chain):
        return [(2, 1)] if self.clue and tuple(chain) == (0,) else []


def _search(sighted: bool, look: float = 0.8) -> RendezvousSearch:
    scenario = parse_mission(THREE).scenario(0)
    search = RendezvousSearch(scenario, 10.0, 15, look, 2, sighted=sighted)
    search.left[0] = 0  # r1 searches, having left g1
    search.checked[0, 0] = True
    return search


def _observe(r1=(5.0, 5.0), last=(4, 6), step=9, clue=False, seen_r3=False):
    poses = np.zeros((3, 3, 3))
    poses[0, :, :2] = [r1, (5.0, 25.0), (25.0, 25.0)]
    seen = np.zeros((3, 3), dtype=bool)
    seen[0, 2] = seen_r3
    last_seen = np.array([[step, last[0], last[1]], [-1, step, -1], [-1, -1, step]])
    known = np.ones((3, 2), dtype=bool)
    return Observations(step, poses, seen, last_seen, known, ~known, _Settled(clue))


def test_the_newest_sighting_first_then_the_older():
    search = _search(sighted=True)
    # r3 (step 6) was seen after r2 (step 4): its sighting first, though both are 20 m
    # (r2) and 28.3 m (r3) away and the nearer goal g2 is unchecked.
    assert search.target(_observe(), 0).tolist() == [25.0, 25.0]
    # At (25, 18), 7 m from r3's sighting (within 0.8 x 10 m), it is looked at: r2's next.
    assert search.target(_observe(r1=(25.0, 18.0)), 0).tolist() == [5.0, 25.0]
    assert search.sightings.looked[0].tolist() == [-1, -1, 6]
    # At (12, 25), 7 m from r2's: both looked at; the known goal g2 is left (23.9 m away,
    # outside 8 m: unchecked).
    assert search.target(_observe(r1=(12.0, 25.0)), 0).tolist() == [25.0, 5.0]


def test_a_teammate_seen_anew_is_looked_for_anew_and_one_in_sight_is_not():
    search = _search(sighted=True)
    search.target(_observe(r1=(25.0, 18.0)), 0)  # r3's sighting of step 6 looked at
    # r3 seen again at step 8, still at (25, 25): a new sighting, newer than r2's.
    assert search.target(_observe(r1=(5.0, 5.0), last=(4, 8)), 0).tolist() == [25.0, 25.0]
    # r3 in sight now (a fresh search, nothing looked at): only r2 is missing.
    assert _search(sighted=True).target(_observe(seen_r3=True), 0).tolist() == [5.0, 25.0]


def test_settles_first_and_goals_only_without_sighted():
    # A missing teammate seen settle (r3 at g2) is looked for at g2 before any sighting.
    assert _search(sighted=True).target(_observe(clue=True), 0).tolist() == [25.0, 5.0]
    # Without ``sighted`` the sightings play no part: the known goal g2, then the sweep.
    assert _search(sighted=False).target(_observe(), 0).tolist() == [25.0, 5.0]


def test_plan_sighted_is_a_switch_and_on_by_default():
    with pytest.raises(EpistemicaError, match="plan_sighted must be true or false"):
        ActiveParameters(plan_sighted=1)
    assert ActiveParameters().plan_sighted is True


def test_not_the_group_it_left_with_nor_a_sighting_at_the_goal_it_left():
    search = _search(sighted=True)
    search.group[0, 2] = True  # r3 stood at g1 with r1 when it left: not missing
    assert search.target(_observe(), 0).tolist() == [5.0, 25.0]
    # r2 last seen at (9, 9), 5.7 m from g1 (within 0.8 x 10 m), the goal r1 left and
    # looked at as it waited: no sighting to look at, the known goal g2 next.
    search = _search(sighted=True)
    observations = _observe(last=(4, -1))
    observations.poses[0, 1, :2] = (9.0, 9.0)
    assert search.target(observations, 0).tolist() == [25.0, 5.0]
    assert search.sightings.looked[0].tolist() == [-1, 4, -1]


def test_sighted_without_a_sensing_range_keeps_no_sightings():
    # Unlimited sensing: nobody searches (``applies`` is False), so nothing to look for.
    scenario = parse_mission(THREE.replace(" range 10", "")).scenario(0)
    assert scenario.sensing_range is None
    assert RendezvousSearch(scenario, 10.0, 15, 0.8, 2, sighted=True).sightings is None


def _meet_step(search: RendezvousSearch, r2_in_sight: bool) -> None:
    """One search step of r1 at (10, 10), off any goal; r2 at (14, 10) in sight or not."""
    poses = np.zeros((3, 3, 3))
    poses[0, :, :2] = [(10.0, 10.0), (14.0, 10.0), (25.0, 25.0)]
    seen = np.zeros((3, 3), dtype=bool)
    seen[0, 1] = r2_in_sight
    last = np.array([[9, 9, -1], [-1, 9, -1], [-1, -1, 9]])
    known = np.ones((3, 2), dtype=bool)
    settles = np.full((3, 3), -1)
    observations = Observations(9, poses, seen, last, known, ~known, _Settled(False), settles)
    search.searchers(observations, np.array([0]))


@pytest.mark.parametrize("sighted", [False, True])
def test_a_meeting_nobody_follows_is_dropped_with_sighted(sighted):
    scenario = parse_mission(THREE).scenario(0)
    search = RendezvousSearch(scenario, 10.0, 15, 0.8, 2, meet=True, sighted=sighted)
    search.left[0] = 0  # r1 searches, having left g1 alone (no group)
    _meet_step(search, r2_in_sight=True)
    # r2, outside its group, in sight: r1 (lower-numbered) leads a meeting to the goal
    # nearest itself, g1 (7.1 m against g2's 15.8 m).
    assert search.leader[0] == 0 and search.meeting[0] == 0
    _meet_step(search, r2_in_sight=False)
    # r2 did not follow. Without ``sighted`` r1 still leads the meeting; with it the
    # meeting is dropped and r1 searches on (it will look where it last saw r2).
    expected = (-1, -1) if sighted else (0, 0)
    assert (search.leader[0], search.meeting[0]) == expected
    assert search.left[0] == 0
