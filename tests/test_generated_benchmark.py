"""The generated benchmark's trial lists (benchmarks/generated_benchmark.py): a family whose
trials do not depend on the trial seed runs one seed, so no trial is counted twice."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import generated_benchmark as gb

from epistemica.mission import parse_mission
from epistemica.sim import simulate


def _mission(family: str, seed: int):
    text = gb.mission_text(family, seed, gb.family_options(family))
    return parse_mission(text, f"{family}_{seed:06d}.epi")


@pytest.mark.parametrize("level", ["rules", "third"])
def test_a_collaborative_trial_does_not_depend_on_its_seed(level):
    # generator seed 2 of the tuning split: a 66-step trial for `rules`
    mission = _mission("collaborative", 2)
    played = [
        simulate(
            mission.scenario(t),
            level,
            seed=t,
            policies=mission.policies(t),
            parameters=mission.parameters,
        ).trajectory
        for t in (0, 30_001)
    ]
    assert played[0].shape == played[1].shape
    assert (played[0] == played[1]).all()


def test_a_goal_trial_depends_on_its_seed():
    # the layout is the mission's, the sightings' noise the trial seed's (tuning mission 1:
    # honest sensing, noise 0.7; in some missions the noise changes no decision)
    mission = _mission("rendezvous", 1)
    played = [
        simulate(
            mission.scenario(t),
            "rules-third",
            seed=t,
            policies=mission.policies(t),
            parameters=mission.parameters,
        ).trajectory
        for t in (0, 1)
    ]
    assert played[0].shape != played[1].shape or (played[0] != played[1]).any()


def test_a_seedless_family_runs_one_seed_and_the_others_every_seed():
    split = gb.SPLITS["locked"]
    assert gb.family_seeds("collaborative", split, 2) == (30_000,)
    assert gb.family_seeds("allocation", split, 2) == (30_000, 30_001)
    per_mission = len(gb.family_levels("collaborative"))
    assert len(gb.trials("collaborative", split, 2, 2)) == 2 * per_mission
    assert len(gb.trials("rendezvous", split, 2, 2)) == 2 * 2 * len(gb.family_levels("x"))
