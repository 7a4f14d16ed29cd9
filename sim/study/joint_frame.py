"""The animation's frame of a joint (collaborative) trial (:class:`JointFrame`, the kind's
:data:`~epistemica.sim.kinds.base.JOINT_PANELS`): each task with the number of robots it
needs (crossed out once done), what each robot steers to (a task, ``explore``, ``fetch``,
``wait``), which robot knows of which task, what one robot knows each teammate knows, the
events. :mod:`epistemica.sim.study.frames` picks it by the trace's kind.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from epistemica.sim.kinds.base import JOINT_PANELS
from epistemica.sim.study.figure_parts import (
    FONT_SIZE,
    draw_events,
    draw_goals,
    draw_obstacles,
    event_panel,
    move_robots,
    pyplot,
    robot_artists,
    robot_table,
    set_map_limits,
    trace_title,
)
from epistemica.sim.study.palette import fetching_robot, robot_colour

__all__ = ["JointFrame"]

_ACTIONS = {-1: "explore", -2: "fetch", -3: "wait"}
#: The same, as what a robot is doing (``simulate``'s text, the trajectory figure's legend).
_DOING = {-1: "exploring", -2: "fetching a teammate", -3: "waiting for helpers"}


def _task_label(trace: dict[str, Any], task: int, step: int) -> str:
    """A task's label on the map at ``step``: the robots it needs, and once done when."""
    done = int(trace["tasks_done"][task])
    finished = f", done at {done}" if 0 <= done <= step else ""
    return f"×{int(trace['needs'][task])}{finished}"


class JointFrame:
    """The animation's figure over a joint (collaborative) trial's trace; :meth:`draw`
    shows one step (see the module docstring).

    Artists carry ``gid`` tags as in :class:`TraceFrame`; :meth:`knows_at` and
    :meth:`nested_at` are the two tables drawn beside the map, read from the trace's
    ``tasks_known`` and ``aware_since``.
    """

    panels = JOINT_PANELS

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
        draw_obstacles(ax, trace.get("obstacles", []))
        draw_goals(ax, self.places, self.tasks, trace["success_radius"])
        self.needs = [int(k) for k in trace["needs"]]
        self.need_labels = [  # robots it needs, and once done when
            ax.annotate(f"×{k}", (x, y), textcoords="offset points", xytext=(7, -12),
                        fontsize=FONT_SIZE, gid=f"needs:{name}")
            for (x, y), k, name in zip(self.places, self.needs, self.tasks, strict=True)
        ]  # fmt: skip
        set_map_limits(ax, self.poses[:, :, :2], self.places, trace["workspace"])
        self.trails, self.discs, self.sensing = robot_artists(
            ax, self.robots, self.poses[0], trace["sensing_range"]
        )
        ax.legend(handles=self.discs, fontsize=FONT_SIZE, loc="upper left",
                  bbox_to_anchor=(-0.02, -0.06), ncol=min(n, 8), frameon=False)  # fmt: skip
        self.others = others = [j for j in range(n) if j != self.focus]
        note = " (dark: knows; columns of tasks done: grey)"
        self.knows_image = robot_table(
            fig.add_subplot(grid[0, 1]),
            self.robots,
            range(n),
            self.tasks,
            "which robot knows of which task" + note,
        )
        self.nested_image = robot_table(
            fig.add_subplot(grid[1, 1]), [self.robots[j] for j in others], others, self.tasks,
            f"what {self.robots[self.focus]} knows each teammate knows of" + note,
        )  # fmt: skip
        self.event_lines = event_panel(fig.add_subplot(grid[2, 1]))
        self.transient: list = []
        self.heading = fig.suptitle("", fontsize=FONT_SIZE + 1)
        fig.subplots_adjust(left=0.05, right=0.97, top=0.91, bottom=0.14, hspace=0.6)

    @staticmethod
    def mark_places(ax, trace: dict[str, Any], step: int) -> None:
        """The tasks on the map ``ax`` at ``step``: the robots each needs, done ones crossed
        with their step, and the robots that steered to each up to ``step``."""
        places = np.asarray(trace["goal_positions"], dtype=float).reshape(-1, 2)
        draw_goals(ax, places, trace["goals"], trace["success_radius"])
        n = len(trace["robots"])
        steer = np.asarray(trace["steer_to"], dtype=int).reshape(-1, n)[: max(step, 0)]
        for t, (x, y) in enumerate(places):
            came = [trace["robots"][i] for i in range(n) if (steer[:, i] == t).any()]
            text = _task_label(trace, t, step) + (
                f"\nsteered to by {', '.join(came)}" if came else ""
            )
            ax.annotate(text, (x, y), textcoords="offset points", xytext=(7, -12), va="top",
                        fontsize=FONT_SIZE, gid=f"needs:{trace['goals'][t]}")  # fmt: skip
            if 0 <= int(trace["tasks_done"][t]) <= step:
                ax.plot(x, y, "x", color="0.5", ms=16, mew=3, gid=f"done:{trace['goals'][t]}")

    @staticmethod
    def status(trace: dict[str, Any], robot: int) -> str:
        """What ``robot`` did at the trace's last decision: the task it steered to, or
        exploring, fetching a teammate, waiting for helpers."""
        steer = trace["steer_to"]
        target = int(steer[-1][robot]) if len(steer) else -1
        return _DOING.get(target) or f"steering to {trace['goals'][target]}"

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
        for t, label in enumerate(self.need_labels):
            label.set_text(_task_label(self.trace, t, step))
        for t in np.flatnonzero(finished):
            self.transient.append(ax.plot(*self.places[t], "x", color="0.5", ms=16, mew=3)[0])
        shade = np.where(finished[None], 0.35, 0.0)  # done columns grey
        self.knows_image.set_data(np.maximum(self.knows_at(step), shade))
        self.nested_image.set_data(np.maximum(self.nested_at(step), shade))
        self.transient += draw_events(self, step, step - 1 if since is None else since)
        self.heading.set_text(f"{self.title}   step {step}")
        return [*self.trails, *self.discs, *self.transient, self.heading]

    def close(self) -> None:
        """Release the figure."""
        self.plt.close(self.fig)
