"""The animation's frame shows obstacles, closed goals, what each robot knows and beliefs
not computed; the trajectory figure shows obstacles and closed goals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from matplotlib.text import Text

from epistemica.mission import load_mission
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.figures import TraceFrame, plot_trial
from epistemica.sim.study.frames import BELIEF_NOTE, SETS_GAP
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
    trial = simulate(s, "rules-first", seed=0)
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
    plot_trial(s, simulate(s, "rules-first", seed=0), tmp_path / "t.png")
    assert (tmp_path / "t.png").stat().st_size > 10_000


PRIVATE = Path(__file__).resolve().parents[2] / "specs" / "nested" / "private_goal_3.epi"


@pytest.fixture(scope="module")
def private_frame():
    """private_goal_3 at seed 4, third: the story of issue 39 (r1 alone knows of g4)."""
    mission = load_mission(str(PRIVATE))
    s = mission.scenario(4)
    trial = simulate(s, "rules-third", seed=4, policies=mission.policies(4))
    frame = TraceFrame(trial_trace(s, trial), "private_goal_3")
    yield trial, frame
    frame.close()


def test_lines_of_equal_values_are_drawn_apart(private_frame):
    trial, frame = private_frame
    frame.draw(0)
    frame.fig.canvas.draw()
    lines = [
        line for line in frame.sets_axes.get_lines() if (line.get_gid() or "").startswith("sets:")
    ]
    assert len(lines) == 3 + 2  # three own sets, r1's model of r2's and r3's
    gap = SETS_GAP * frame.fig.dpi / 72
    shown = [
        line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))[:, 1]
        for line in lines
    ]
    coinciding = 0
    for a in range(len(lines)):
        for b in range(a + 1, len(lines)):
            equal = lines[a].get_ydata() == lines[b].get_ydata()
            coinciding += int(equal.sum()) * (lines[a].get_linestyle() != lines[b].get_linestyle())
            assert (np.abs(shown[a] - shown[b])[equal] >= gap * 0.99).all()
    # a model equal to a teammate's own set: it happens here (r1 models r2 and r3 exactly)
    f = frame.focus
    assert (trial.modelled[:, f, 1] == trial.considered[:, 1]).any() and coinciding > 0


def test_no_text_leaves_the_frame(private_frame):
    trial, frame = private_frame
    for step in (0, trial.steps // 2, trial.steps):
        frame.draw(step)
        renderer = frame.fig.canvas.get_renderer()
        page = frame.fig.bbox
        for text in frame.fig.findobj(Text):
            if not (text.get_visible() and text.get_text().strip()):
                continue
            box = text.get_window_extent(renderer)
            inside = (
                page.x0 <= box.x0 and box.x1 <= page.x1 and page.y0 <= box.y0 <= box.y1 <= page.y1
            )
            assert inside, (step, text.get_text()[:40], box.bounds)


def test_belief_at_step_0_is_explained_where_it_is_certain(private_frame):
    trial, frame = private_frame
    # Certain before any event (the prior from the starting positions): and the frame says why.
    assert trial.goal_belief[0].max() > 0.99
    notes = [t.get_text() for t in frame.fig.findobj(Text) if t.get_gid() == "belief-note"]
    assert notes == [BELIEF_NOTE] and "step 0" in BELIEF_NOTE and "prior" in BELIEF_NOTE
