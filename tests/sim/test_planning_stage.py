"""The planning stage: the draws that stand for a teammate never seen."""

from __future__ import annotations

import numpy as np

from epistemica.sim import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage


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
