"""The expected-free-energy controller against a from-definitions recomputation."""

from __future__ import annotations

import numpy as np
import pytest

from epistemica.aif import (
    Controller,
    bayes_update,
    control_grid,
    decide,
    evidence_by_order,
    expected_free_energy,
    goal_log_probabilities,
    kl_divergence,
    log_likelihood,
    perspective_sets,
    predict_poses,
    published_update,
    valid_configurations,
)

ETA, ETA_B, EPS = 20.0, 0.8, 0.01


def reference_terms(goals, sensors, configs, order, robot, poses, x, prior, update="bayes"):
    """G of robot ``robot`` at position ``x``, recomputed from the documented definition
    with the public building blocks only (no grouping trick, no batching)."""
    pos_now = np.asarray(poses, dtype=float)[:, :2]
    pos_next = pos_now.copy()
    pos_next[robot] = x
    k = configs.shape[0]

    def belief(e):
        L = np.exp(log_likelihood(goal_log_probabilities(e), configs))
        return bayes_update(prior, L) if update == "bayes" else published_update(prior, L)

    def ev(agent, depth, pos):
        # Each row's evidence is the mean of the terms that reach it: one per chain whose
        # last robot measures the row (never itself), and the agent's own position.
        terms = np.zeros(len(sensors))
        terms[agent] += 1
        for chains in perspective_sets(sensors, agent, depth)[1:]:
            for chain in chains:
                terms += np.arange(len(sensors)) != chain[-1]
        total = evidence_by_order(agent, pos, goals, sensors, depth, ETA, ETA_B).sum(axis=0)
        return total / np.maximum(terms, 1)[:, None]

    levels = perspective_sets(sensors, robot, order)
    persp = [(robot, order)]
    if order >= 2:
        persp += [(chain[-1], order - 1) for chain in levels[2]]
    if order >= 3:
        persp += [(chain[-1], order - 2) for chain in levels[3]]
    e_root_now = ev(robot, order, pos_now)
    q_now = belief(e_root_now)
    focal = int(np.argmax(q_now))
    pref = np.full(k, EPS / k)
    pref[focal] += 1 - EPS
    risks = []
    for idx, (agent, depth) in enumerate(persp):
        now, nxt = ev(agent, depth, pos_now), ev(agent, depth, pos_next)
        e = nxt.copy()
        if idx == 0:
            e[robot] = now[robot]  # own motion is not evidence about own goal
            e_root_next = e
        else:
            mask = np.arange(len(sensors)) != robot
            e[mask] = now[mask]  # the others see robot move; their own views stay
        risks.append(kl_divergence(belief(e), pref))
    L = np.exp(log_likelihood(goal_log_probabilities(e_root_next), configs))
    ell = L / L.max()
    reading = expected_free_energy(q_now, np.stack([ell, 1 - ell])).G
    goal = goals[configs[focal, robot]]
    progress = np.hypot(*(np.asarray(x) - goal)) / ETA
    return progress, float(np.mean(risks)), reading


SCENES = [
    (["range", "bearing", "range"], "allocation", None),
    (["bearing", "bearing", "range", "range"], "allocation", None),
    (["bearing", "range", "bearing"], "capacity", [1, 2]),
    (["range", "range", "range"], "rendezvous", None),
]


@pytest.mark.parametrize("scene", range(len(SCENES)))
@pytest.mark.parametrize("order", [0, 1, 2, 3])
@pytest.mark.parametrize("update", ["bayes", "published"])
def test_controller_matches_definition(scene, order, update):
    sensors, mission, caps = SCENES[scene]
    n = len(sensors)
    rng = np.random.default_rng(10 * scene + order)
    m = n if caps is None else len(caps)
    goals = rng.uniform(0, 30, (m, 2))
    configs = valid_configurations(mission, n, m, capacities=caps)
    poses = np.column_stack([rng.uniform(0, 30, (n, 2)), rng.uniform(-np.pi, np.pi, n)])
    prior = rng.dirichlet(np.ones(configs.shape[0]))
    ctrl = Controller(
        goals,
        sensors,
        configs,
        order=order,
        eta=ETA,
        eta_bearing=ETA_B,
        update=update,
        preference_floor=EPS,
        progress_weight=1.0,  # the reference below computes the unweighted term
    )
    for robot in range(n):
        cands = predict_poses(poses[robot], ctrl.controls)[:, :2]
        terms = ctrl.terms(robot, poses, cands, prior=prior)
        for j in (0, 5, 13, 31):
            p, r, rd = reference_terms(
                goals, sensors, configs, order, robot, poses, cands[j], prior, update
            )
            assert terms.progress[j] == pytest.approx(p, abs=1e-9)
            assert terms.belief_risk[j] == pytest.approx(r, abs=1e-9)
            assert terms.reading[j] == pytest.approx(rd, abs=1e-9)


def test_control_grid_and_dynamics():
    grid = control_grid()
    assert grid.shape == (32, 2)
    assert any((grid[:, 0] == 0) & (grid[:, 1] == 0)) and any((grid[:, 0] == 1) & (grid[:, 1] == 0))
    # Turn first (to pi/2), then move 2 m * 1.5 s along the new heading.
    np.testing.assert_allclose(
        predict_poses([1.0, 1.0, 0.0], [[2.0, np.pi / 2]], dt=1.5),
        [[1.0, 4.0, np.pi / 2]],
        atol=1e-12,
    )


def _two_robots(**options):
    goals = [[10.0, 0.0], [-10.0, 0.0]]
    return Controller(
        goals, ["range", "range"], valid_configurations("allocation", 2, 2), **options
    )


def test_drives_straight_to_its_goal():
    d = _two_robots(order=2).decide(0, [[8.0, 0.0, 0.0], [-8.0, 0.0, 0.0]])
    assert d.control == (1.0, 0.0)
    assert d.focal == 0 and d.q_pi.sum() == pytest.approx(1.0)


def test_focal_point_is_recomputed_from_current_observations():
    ctrl = _two_robots(order=1)
    _, focal = ctrl.beliefs(0, [[0.0, 1.0], [9.0, 0.0]])  # robot 1 sits on goal 0
    assert ctrl.configurations[focal].tolist() == [1, 0]
    _, focal = ctrl.beliefs(0, [[0.0, 1.0], [-9.0, 0.0]])  # ...now on goal 1
    assert ctrl.configurations[focal].tolist() == [0, 1]


def test_own_motion_is_not_evidence_about_own_goal():
    poses = [[0.0, 3.0, 0.0], [2.0, -1.0, 0.0]]
    cands = predict_poses(poses[0], control_grid())[:, :2]
    first = _two_robots(order=1).terms(0, poses, cands)
    # A range robot's own belief cannot move with its own control: no epistemic value
    # and no belief risk difference between controls.
    assert np.ptp(first.reading) == 0.0 and np.ptp(first.belief_risk) == 0.0
    # At order 2 robot 1 sees it move: the modelled belief of robot 1 does change.
    second = _two_robots(order=2).terms(0, poses, cands)
    assert np.ptp(second.belief_risk) > 0


def test_bearing_robot_gains_information_by_moving():
    goals = [[10.0, 0.0], [0.0, 10.0]]
    ctrl = Controller(goals, ["bearing", "range"], valid_configurations("allocation", 2, 2))
    poses = [[0.0, 0.0, 0.0], [5.0, 5.0, 0.0]]  # robot 1 halfway between the goals
    t = ctrl.terms(0, poses, predict_poses(poses[0], control_grid())[:, :2])
    assert np.ptp(t.reading) > 0


def test_horizon_search():
    poses = [[0.0, 0.0, np.pi], [-5.0, 0.0, 0.0]]
    one = _two_robots(order=2).decide(0, poses)
    three = _two_robots(order=2, horizon=3).decide(0, poses)
    assert np.all(np.isfinite(three.G))
    assert three.control == one.control == (1.0, -np.pi)  # turn round, go to goal 0
    # A longer look-ahead accumulates more cost per first control.
    assert np.all(three.G >= one.G)


def test_sampled_decisions_are_reproducible():
    ctrl = _two_robots(order=2, gamma=50.0)
    poses = [[0.0, 0.0, 0.0], [-5.0, 0.0, 0.0]]
    a = ctrl.decide(0, poses, rng=np.random.default_rng(3))
    b = ctrl.decide(0, poses, rng=np.random.default_rng(3))
    assert a.index == b.index
    assert a.q_pi[a.index] > 0


def test_function_form():
    d = decide(
        0,
        [[0.0, 0.0, 0.0]],
        [[5.0, 0.0], [0.0, 5.0]],
        ["range"],
        valid_configurations("allocation", 1, 2),
    )
    assert d.control == (1.0, 0.0)


def test_chunked_passes_agree(monkeypatch):
    import epistemica.aif.one_step as one_step_module

    sensors = ["bearing", "range", "bearing", "range"]
    rng = np.random.default_rng(5)
    goals = rng.uniform(0, 30, (4, 2))
    poses = np.column_stack([rng.uniform(0, 30, (4, 2)), np.zeros(4)])
    configs = valid_configurations("allocation", 4, 4)
    cands = predict_poses(poses[0], control_grid())[:, :2]
    whole = Controller(goals, sensors, configs, order=3).terms(0, poses, cands)
    monkeypatch.setattr(one_step_module, "CHUNK_CELLS", 50)  # two rows' worth per chunk
    chunked = Controller(goals, sensors, configs, order=3).terms(0, poses, cands)
    np.testing.assert_allclose(chunked.G, whole.G, atol=1e-12)


def test_float32_passes_for_large_sets_agree_with_float64(monkeypatch):
    import epistemica.aif.one_step as one_step_module

    n = 8
    rng = np.random.default_rng(2)
    goals = rng.uniform(1, 29, (n, 2))
    poses = np.column_stack([rng.uniform(0, 30, (n, 2)), np.zeros(n)])
    sensors = ["bearing", "range", "bearing", "range", "range", "bearing", "range", "range"]
    configs = valid_configurations("allocation", n, n)  # 40,320 rows: float32 passes
    cands = predict_poses(poses[0], control_grid())[:, :2]
    g32 = Controller(goals, sensors, configs, order=3).evaluate(0, poses, cands)
    monkeypatch.setattr(one_step_module, "FLOAT32_ROWS", 10**9)
    g64 = Controller(goals, sensors, configs, order=3).evaluate(0, poses, cands)
    np.testing.assert_allclose(g32, g64, atol=5e-5)
    assert np.argmin(g32) == np.argmin(g64)
