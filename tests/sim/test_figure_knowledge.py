"""The animation's frame shows obstacles, closed goals, what each robot knows and beliefs
not computed; the trajectory figure shows obstacles and closed goals."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from epistemica.sim import Scenario, simulate
from epistemica.sim.study.figures import TraceFrame, plot_trial
from epistemica.sim.study.trace import trial_trace

SQUARE = [[10.0, 4.0], [13.0, 4.0], [13.0, 7.0], [10.0, 7.0]]


def _scenario() -> Scenario:
    known = np.array([[True, True, True], [True, True, False]])  # r1 alone knows of g3
    return Scenario(
        "rendezvous", [[3.0, 3.0], [25.0, 25.0]], [[5.0, 25.0], [25.0, 5.0], [15.0, 15.0]],
        ["range"] * 2, workspace=30.0, closed=[False, True, False], obstacles=[SQUARE],
        known_goals=known, discovery_range=1.0, max_steps=5,
    )  # fmt: skip


def _gids(ax) -> list[str]:
    return [a.get_gid() for a in ax.get_children() if a.get_gid()]


def test_frame_draws_obstacles_closed_goals_and_knowledge():
    s = _scenario()
    trial = simulate(s, "first", seed=0)
    frame = TraceFrame(trial_trace(s, trial))
    try:
        frame.draw(2)
        assert "obstacle:0" in _gids(frame.map_axes)
        stars = {a.get_gid(): a for a in frame.map_axes.get_lines() if a.get_gid()}
        assert stars["goal:g2"].get_markerfacecolor() == "w"  # closed: hollow
        assert stars["goal:g1"].get_markerfacecolor() == "k"
        text = frame.knowing.get_text().splitlines()
        assert text[:3] == ["knows of:", "r1 g1 g2 g3", "r2 g1 g2"]
        assert "r1: r2 does" in text[3] and "not know of g3" in text[4]
        # A robot with no belief at a step reads n/c, not 0.00.
        belief = trial.goal_belief[2]
        for i, row in enumerate(frame.belief_numbers):
            texts = [t.get_text() for t in row]
            if belief[i].sum() == 0:
                assert texts == ["n/c"] * 3
            elif not trial.known_goals[2, i, i, 2]:
                assert texts[2] == "·"
    finally:
        frame.close()


def test_trajectory_figure_draws_obstacles_and_closed_goals(tmp_path):
    s = _scenario()
    plot_trial(s, simulate(s, "first", seed=0), tmp_path / "t.png")
    assert (tmp_path / "t.png").stat().st_size > 10_000
