"""Where a robot expects a teammate it does not see (sim/policies/collaborative_teammates.py): the
starts a never-seen teammate may have had, and the waypoint a teammate seen off its
sweep makes for, each on a scene worked by hand or as a law."""

from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.sim.policies.collaborative_teammates import TeammateModel


def _world(workspace: float = 40.0, sensing_range: float = 10.0) -> SimpleNamespace:
    # two lanes, x = 10 and x = 30 (at 40 m and 10 m sight); robot 1 sweeps
    # (30, 30) -> (30, 10) -> (10, 10) -> (10, 30) -> (30, 30) -> ...
    return SimpleNamespace(
        workspace=workspace,
        sensing_range=sensing_range,
        n_robots=2,
        max_steps=100,
        max_speed=np.array([1.0, 1.0]),
    )


def _sees(step: int, poses, model: TeammateModel, last_seen, estimates) -> None:
    gap = np.hypot(*(poses[:, None, :2] - poses[None, :, :2]).transpose(2, 0, 1))
    seen = gap <= model.s.sensing_range
    last_seen[seen] = step
    rows, cols = np.nonzero(seen)
    estimates[rows, cols] = poses[cols, :2]
    model.observe(step, poses, estimates, last_seen)


def test_a_teammate_seen_off_its_sweep_makes_for_the_waypoint_its_motion_points_at():
    model = TeammateModel(_world(), lane_factor=2.0, particles=0, resume=True)
    route = model.routes[1]
    assert route.points[:3].tolist() == [[30.0, 30.0], [30.0, 10.0], [10.0, 10.0]]
    last_seen, estimates = np.full((2, 2), -1), np.zeros((2, 2, 2))
    # robot 1 moves 1 m a step along (0.8, 0.6): from (22, 4) that is 10 m to (30, 10),
    # 6 m off the sweep; robot 0 sees it at steps 10 and 11, then no more
    for step, place in ((10, (21.2, 3.4)), (11, (22.0, 4.0))):
        poses = np.array([[20.0, 0.0, 0.0], [*place, 0.0]])
        _sees(step, poses, model, last_seen, estimates)
    assert model.resume[0, 1] == 1
    seen = int(last_seen[0, 1])
    # five steps on: half way along the 10 m leg
    assert np.allclose(model.place(16, 0, 1, estimates[0, 1], seen), [26.0, 7.0])
    # fourteen steps on: 4 m past (30, 10) towards (10, 10)
    assert np.allclose(model.place(25, 0, 1, estimates[0, 1], seen), [26.0, 10.0])
    assert model.arc(25, 0, 1, estimates[0, 1], seen) == 20.0 + 4.0


def test_without_resume_a_teammate_seen_off_its_sweep_is_put_on_its_nearest_point():
    model = TeammateModel(_world(), lane_factor=2.0, particles=0, resume=False)
    # (22, 4) is nearest (22, 10), arc 20 + 8 on the sweep; 5 steps later 5 m further
    assert np.allclose(model.place(16, 0, 1, np.array([22.0, 4.0]), 11), [17.0, 10.0])


def test_a_standing_teammate_shows_no_waypoint():
    model = TeammateModel(_world(), lane_factor=2.0, particles=0, resume=True)
    last_seen, estimates = np.full((2, 2), -1), np.zeros((2, 2, 2))
    for step in (10, 11):  # at a task off the sweep, not moving
        _sees(step, np.array([[20.0, 0.0, 0.0], [22.0, 4.0, 0.0]]), model, last_seen, estimates)
    assert model.resume[0, 1] == -1


@settings(max_examples=60, deadline=None)
@given(
    particles=st.integers(2, 6),
    start=st.integers(0, 35),
    walk=st.lists(st.tuples(st.floats(0, 40), st.floats(0, 40)), min_size=1, max_size=40),
)
def test_the_true_start_of_a_teammate_never_seen_is_never_ruled_out(particles, start, walk):
    """Soundness of pruning: a teammate that started on the grid and kept to the
    convention, never in sight, keeps its start among the possible ones; a start is
    ruled out only if it would have put the teammate in sight at some step."""
    model = TeammateModel(_world(), lane_factor=2.0, particles=particles, resume=True)
    g = start % len(model.starts)
    last_seen, estimates = np.full((2, 2), -1), np.zeros((2, 2, 2))
    in_sight = np.zeros(len(model.starts), dtype=bool)
    route = model.routes[1]
    legs = np.hypot(*(route.points[0] - model.starts).T)
    for step, here in enumerate(walk):
        # straight from each start to the sweep's first waypoint at 1 m a step, then on it
        on_leg = (step < legs)[:, None]
        toward = (
            model.starts
            + (route.points[0] - model.starts) * (step / np.maximum(legs, 1e-9))[:, None]
        )
        truth = np.where(on_leg, toward, route.along(np.maximum(step - legs, 0.0)))
        poses = np.array([[*here, 0.0], [*truth[g], 0.0]])
        in_sight |= np.hypot(*(truth - np.array(here)).T) <= 10.0
        last_seen[:] = np.where(np.eye(2, dtype=bool), step, last_seen)
        if np.hypot(*(truth[g] - np.array(here))) <= 10.0:
            return  # seen: the starts no longer matter
        _sees(step, poses, model, last_seen, estimates)
        assert model.alive[0, 1, g]
    assert (model.alive[0, 1] == ~in_sight).all()
