"""Pictures of a trial: trajectories (PNG, PDF, SVG) and an animation of what each robot
knows (GIF), for every mission kind.

matplotlib is imported only when drawing (:mod:`epistemica.sim.study.figure_parts`, the shared
drawing parts), with the Agg backend (no display needed); without it the functions raise an
:class:`~epistemica.del_.errors.EpistemicaError` naming the extra to install (``pip install
'epistemica[plot]'``). GIFs are written by Pillow.

The animation is drawn from a trial's trace (:mod:`epistemica.sim.study.trace`), so a stored
trace draws the same picture as the trial itself. Goals and robots cannot be confused:
goals (tasks) are black stars (their success radius a grey disc), labelled with the
mission's names; robots take a qualitative palette without grey. The map shows each robot
(disc, heading, trail), its sensing radius (dashed circle) and rings around the robots that
observed an event at that moment; obstacles are dark polygons, a closed goal a hollow star.
Beside the map are the panels the mission's kind names
(:class:`~epistemica.sim.kinds.base.MissionKind` ``panels``), drawn by the frame
:func:`~epistemica.sim.study.frames.frame_for` picks (:mod:`epistemica.sim.study.frames`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.trial import Trial
from epistemica.sim.study.figure_parts import (
    FONT_SIZE,
    draw_goals,
    draw_obstacles,
    pyplot,
    save_figure,
    set_map_limits,
    trace_title,
    write_gif,
)
from epistemica.sim.study.frames import FRAMES, JointFrame, TraceFrame, frame_for, frame_type
from epistemica.sim.study.palette import ROBOT_COLOURS, fetching_robot, focus_robot, robot_colour
from epistemica.sim.study.trace import trial_trace

__all__ = [
    "FONT_SIZE",
    "FRAMES",
    "ROBOT_COLOURS",
    "JointFrame",
    "TraceFrame",
    "animate_trace",
    "animate_trial",
    "draw_goals",
    "fetching_robot",
    "focus_robot",
    "frame_for",
    "plot_trial",
    "pyplot",
    "save_figure",
    "set_map_limits",
    "write_gif",
]


def plot_trial(scenario: Scenario, trial: Trial, path) -> None:
    """Write the trajectories of ``trial`` in ``scenario`` as a figure at ``path`` (the
    extension picks the format: ``.png``, ``.pdf``, ``.svg``), of any kind: the places are
    drawn by the frame of the kind's panels (:func:`~epistemica.sim.study.frames.frame_type`:
    goals, closed ones hollow; or tasks with the robots each needs, when each was done and
    who steered to it), and each robot's legend entry says what it did last.

    Examples
    --------
    >>> import os, tempfile
    >>> from epistemica.sim import Scenario, simulate
    >>> s = Scenario.paper("rendezvous", 2, 2, seed=0)
    >>> path = os.path.join(tempfile.mkdtemp(), "t.png")
    >>> plot_trial(s, simulate(s, "convention", seed=0), path)
    >>> os.path.getsize(path) > 10_000
    True
    >>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
    >>> c = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1).replace(max_steps=8)
    >>> plot_trial(c, simulate(c, "third", seed=1), path)
    """
    plt = pyplot()
    trace = trial_trace(scenario, trial)
    frame = frame_type(trace)
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    draw_obstacles(ax, trace.get("obstacles", []))
    frame.mark_places(ax, trace, int(trace["steps"]))
    poses = np.asarray(trace["poses"], dtype=float)
    for i, name in enumerate(trace["robots"]):
        colour = robot_colour(i)
        label = f"{name} ({trace['sensors'][i]}, {trace['policies'][i]}): {frame.status(trace, i)}"
        ax.plot(poses[:, i, 0], poses[:, i, 1], "-", color=colour, linewidth=1.6, label=label)
        ax.plot(*poses[0, i, :2], "o", color=colour, markeredgecolor="k")
        ax.plot(*poses[-1, i, :2], "s", color=colour, markeredgecolor="k")
    places = np.asarray(trace["goal_positions"], dtype=float).reshape(-1, 2)
    set_map_limits(ax, poses[:, :, :2], places, trace["workspace"])
    ax.set_title(trace_title(trace, scenario.kind.name), fontsize=FONT_SIZE)
    ax.legend(
        fontsize=FONT_SIZE, loc="upper right", title="o start, ■ end", title_fontsize=FONT_SIZE
    )
    fig.tight_layout()
    save_figure(fig, path, "png")
    plt.close(fig)


def animate_trace(trace: dict[str, Any], path, fps: int = 6, mission: str = "") -> int:
    """Write an animated GIF of a trial's trace, of any kind (:func:`frame_for`); the frame
    count.

    At most 60 frames (steps subsampled evenly, the first and last always shown); an event
    is ringed in the frame that first shows its step.
    """
    return write_gif(frame_for(trace, mission), int(trace["steps"]), path, fps)


def animate_trial(scenario: Scenario, trial: Trial, path, fps: int = 6) -> int:
    """Write an animated GIF of ``trial`` (see :func:`animate_trace`); the frame count.

    Examples
    --------
    >>> import os, tempfile
    >>> from epistemica.sim import Scenario, simulate
    >>> s = Scenario.paper("allocation", 2, seed=0).replace(max_steps=6)
    >>> animate_trial(s, simulate(s, "third", seed=0), os.path.join(tempfile.mkdtemp(), "t.gif"))
    7
    >>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
    >>> c = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1).replace(max_steps=8)
    >>> animate_trial(c, simulate(c, "third", seed=1), os.path.join(tempfile.mkdtemp(), "t.gif"))
    9
    """
    pyplot()  # the clear error before any work
    return animate_trace(trial_trace(scenario, trial), path, fps, scenario.kind.name)
