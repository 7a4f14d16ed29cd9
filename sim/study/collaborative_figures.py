"""An animation of a collaborative trial (:mod:`epistemica.sim.kinds.collaborative`) from its
trace (:func:`epistemica.sim.study.trace.trial_trace`): what each robot knows, and what one
robot knows its teammates know.

The map shows the tasks (black stars labelled with how many robots each needs, crossed
out once done), each robot (disc, trail, dashed sensing circle) with what it does
(``explore``, ``fetch``, or the task it heads to) and rings around the robots that observed
an event at that moment. Beside it: which robot knows of which task, and what one robot
(the one that fetched teammates most often: its reason to fetch is a teammate that does
not know) knows each teammate knows, both read from the trace's ``tasks_known`` and
``aware_since``; and the events observed so far with their observers.

Examples
--------
>>> import os, tempfile
>>> from epistemica.sim import simulate
>>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
>>> from epistemica.sim.study.trace import trial_trace
>>> s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1).replace(max_steps=8)
>>> trace = trial_trace(s, simulate(s, "third", seed=1))
>>> animate_collaborative(trace, os.path.join(tempfile.mkdtemp(), "t.gif"))
9
"""

from __future__ import annotations

from typing import Any

import numpy as np

from epistemica.sim.study.figures import (
    FONT_SIZE,
    draw_events,
    draw_goals,
    event_panel,
    move_robots,
    pyplot,
    robot_artists,
    set_map_limits,
    trace_title,
    write_gif,
)
from epistemica.sim.study.palette import robot_colour

__all__ = ["CollaborativeFrame", "animate_collaborative", "fetching_robot"]

_ACTIONS = {-1: "explore", -2: "fetch"}


def fetching_robot(trace: dict[str, Any]) -> int:
    """The robot whose nested knowledge the animation shows: the one that fetched a
    teammate on the most steps (the lowest index on a tie, robot 0 if none did)."""
    steer = np.asarray(trace["steer_to"], dtype=int).reshape(-1, len(trace["robots"]))
    return int(np.argmax((steer == -2).sum(axis=0)))


class CollaborativeFrame:
    """The animation's figure over a collaborative trace; :meth:`draw` shows one step.

    Artists carry ``gid`` tags (``robot:NAME``, ``sensing:NAME``, ``event:NAME``) as in
    :class:`~epistemica.sim.study.figures.TraceFrame`; :meth:`knows_at` and :meth:`nested_at` are
    the two tables drawn beside the map.
    """

    def __init__(self, trace: dict[str, Any], mission: str = "", focus: int | None = None):
        self.plt = plt = pyplot()
        self.trace = trace
        self.robots, self.tasks = list(trace["robots"]), list(trace["goals"])
        n, m = len(self.robots), len(self.tasks)
        self.poses = np.asarray(trace["poses"], dtype=float)
        self.knows = np.asarray(trace["tasks_known"], dtype=int).reshape(-1, n, m)
        self.steer = np.asarray(trace["steer_to"], dtype=int).reshape(-1, n)
        self.since = np.asarray(trace["aware_since"], dtype=int).reshape(n, n, m)
        self.done = np.asarray(trace["tasks_done"], dtype=int)
        self.places = np.asarray(trace["goal_positions"], dtype=float).reshape(-1, 2)
        self.focus = fetching_robot(trace) if focus is None else focus
        self.title = trace_title(trace, mission)
        self.fig = fig = plt.figure(figsize=(13.0, 7.0))
        grid = fig.add_gridspec(3, 2, width_ratios=(1.0, 1.05), height_ratios=(1.0, 1.0, 0.8))
        self.map_axes = ax = fig.add_subplot(grid[:, 0])
        self.knows_axes = fig.add_subplot(grid[0, 1])
        self.nested_axes = fig.add_subplot(grid[1, 1])
        self.events_axes = fig.add_subplot(grid[2, 1])
        draw_goals(ax, self.places, self.tasks, trace["success_radius"])
        for (x, y), k in zip(self.places, trace["needs"], strict=True):  # robots it needs
            ax.annotate(f"×{k}", (x, y), textcoords="offset points", xytext=(7, -12),
                        fontsize=FONT_SIZE)  # fmt: skip
        set_map_limits(ax, self.poses[:, :, :2], self.places, trace["workspace"])
        self.trails, self.discs, self.sensing = robot_artists(
            ax, self.robots, self.poses[0], trace["sensing_range"]
        )
        ax.legend(handles=self.discs, fontsize=FONT_SIZE, loc="upper left",
                  bbox_to_anchor=(-0.02, -0.06), ncol=min(n, 8), frameon=False)  # fmt: skip
        self.others = others = [j for j in range(n) if j != self.focus]
        self.knows_image = self._table(
            self.knows_axes, self.robots, range(n), "which robot knows of which task"
        )
        self.nested_image = self._table(
            self.nested_axes,
            [self.robots[j] for j in others],
            others,
            f"what {self.robots[self.focus]} knows each teammate knows of",
        )
        self.event_lines = event_panel(self.events_axes)
        self.transient: list = []
        self.heading = fig.suptitle("", fontsize=FONT_SIZE + 1)
        fig.subplots_adjust(left=0.05, right=0.97, top=0.91, bottom=0.14, hspace=0.6)

    def _table(self, ax, names: list[str], robots, title: str):
        image = ax.imshow(np.zeros((len(names), len(self.tasks))), cmap="Greys", vmin=0,
                          vmax=1.6, aspect="auto", interpolation="nearest")  # fmt: skip
        ax.set_xticks(np.arange(len(self.tasks)), self.tasks, fontsize=FONT_SIZE)
        ax.set_yticks(np.arange(len(names)), names, fontsize=FONT_SIZE)
        for label, i in zip(ax.get_yticklabels(), robots, strict=True):
            label.set_color(robot_colour(i))
            label.set_fontweight("bold")
        ax.set_title(title + " (dark: knows; columns of tasks done: grey)", fontsize=FONT_SIZE,
                     loc="left")  # fmt: skip
        return image

    def knows_at(self, step: int) -> np.ndarray:
        """``(n, m)`` 1 where robot ``i`` knew of task ``t`` at ``step``."""
        return self.knows[min(step, len(self.knows) - 1)]

    def nested_at(self, step: int) -> np.ndarray:
        """``(n - 1, m)`` 1 where the focus robot knew at ``step`` that each teammate (in
        robot order, the focus robot left out) knows of task ``t``."""
        since = self.since[self.focus, self.others]
        return ((since >= 0) & (since <= step)).astype(int)

    def draw(self, step: int, since: int | None = None) -> list:
        """Show ``step`` (events of steps after ``since`` ringed on the map); the artists."""
        for artist in self.transient:
            artist.remove()
        self.transient.clear()
        ax, pose = self.map_axes, self.poses[step]
        decided = min(step, len(self.steer) - 1)
        move_robots(self, step)
        for i in range(len(self.robots)):
            target = int(self.steer[decided, i]) if decided >= 0 else -1
            action = _ACTIONS.get(target) or f"→{self.tasks[target]}"
            label = ax.text(pose[i, 0] + 1.0, pose[i, 1] + 1.0, action,
                            fontsize=FONT_SIZE - 1, color=robot_colour(i))  # fmt: skip
            self.transient.append(label)
        finished = (self.done >= 0) & (self.done <= step)
        for t in np.flatnonzero(finished):
            self.transient.append(ax.plot(*self.places[t], "x", color="0.5", ms=16, mew=3)[0])
        shade = np.where(finished[None], 0.35, 0.0)  # done columns grey
        self.knows_image.set_data(np.maximum(self.knows_at(step), shade))
        self.nested_image.set_data(np.maximum(self.nested_at(step), shade))
        self._draw_events(step, step - 1 if since is None else since)
        self.heading.set_text(f"{self.title}   step {step}")
        return [*self.trails, *self.discs, *self.transient, self.heading]

    def _draw_events(self, step: int, since: int) -> None:
        self.transient += draw_events(self, step, since)

    def close(self) -> None:
        """Release the figure."""
        self.plt.close(self.fig)


def animate_collaborative(trace: dict[str, Any], path, fps: int = 6, mission: str = "") -> int:
    """Write an animated GIF of a collaborative trial's trace (see the module docstring);
    the frame count (at most 60, steps subsampled evenly)."""
    return write_gif(CollaborativeFrame(trace, mission), int(trace["steps"]), path, fps)
