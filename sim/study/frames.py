"""The animation's frames: one figure per set of panels a mission kind names, the map on the
left and the kind's panels (:class:`~epistemica.sim.kinds.base.MissionKind` ``panels``)
beside it; :meth:`draw` shows one step of a trace (:mod:`epistemica.sim.study.trace`).

- :class:`TraceFrame` (:data:`~epistemica.sim.kinds.base.GOAL_PANELS`, goal and multitask
  missions): each robot's belief about its own goal (``n/c`` where it was not computed,
  ``·`` on a goal it does not know of), what each robot knows of (and what the focus robot
  takes each teammate not to know of), the configuration-set sizes over time (own solid,
  the focus robot's model of each teammate's dashed), the events; on the map, where each
  robot places each teammate.
- :class:`JointFrame` (:data:`~epistemica.sim.kinds.base.JOINT_PANELS`, collaborative
  missions; in :mod:`epistemica.sim.study.joint_frame`): each task with the number of
  robots it needs (crossed out once done), what each robot steers to (a task, ``explore``,
  ``fetch``, ``wait``), which robot knows of which task, what one robot knows each teammate
  knows, the events.

:func:`frame_for` picks the frame whose panels are the trace's kind's (:data:`FRAMES`);
:mod:`epistemica.sim.study.figures` writes the animation.
"""

from __future__ import annotations

import textwrap
from typing import Any

import numpy as np

from epistemica.aif.teammates import TYPE_PRIOR
from epistemica.del_.errors import EpistemicaError
from epistemica.sim.kinds.base import GOAL_PANELS
from epistemica.sim.kinds.registry import kind_of_trace
from epistemica.sim.study.figure_parts import (
    FONT_SIZE,
    draw_events,
    draw_goals,
    draw_obstacles,
    event_panel,
    move_robots,
    pyplot,
    robot_artists,
    set_closed,
    set_map_limits,
    trace_title,
)
from epistemica.sim.study.joint_frame import JointFrame
from epistemica.sim.study.palette import (
    TYPE_MEANINGS,
    focus_robot,
    robot_colour,
)
from epistemica.sim.study.trace import known_goals

__all__ = [
    "BELIEF_NOTE",
    "FRAMES",
    "SETS_GAP",
    "JointFrame",
    "TraceFrame",
    "frame_for",
    "frame_type",
]

#: Points between two lines of the configuration-set plot (own sets above, models below):
#: a model equal to a teammate's own set shows beside it, not under it.
SETS_GAP = 1.5
#: Why a belief can read 1.00 at step 0, before any event (under the goal frame's panels).
BELIEF_NOTE = (
    "Beliefs are after each step's observations. At step 0 a robot has seen only\n"
    "where its teammates start: a 1.00 there is its prior (the team taken to be\n"
    "efficient; at orders 2-3, each teammate predicted from the goals it knows of)."
)


class TraceFrame:
    """The animation's figure over a goal trial's trace; :meth:`draw` shows one step.

    Artists carry ``gid`` tags (``robot:NAME``, ``sensing:NAME``, ``goal:NAME``,
    ``estimate:A->B``, ``event:NAME``) so that tests and tools can find them.

    Examples
    --------
    >>> from epistemica.sim import Scenario, simulate
    >>> from epistemica.sim.study.trace import trial_trace
    >>> s = Scenario.paper("rendezvous", 3, seed=0, max_steps=5, sensing_range=8.0)
    >>> frame = TraceFrame(trial_trace(s, simulate(s, "third", seed=0)))
    >>> len(frame.sensing), frame.belief_axes.get_xticklabels()[0].get_text()
    (3, 'g1')
    >>> frame.close()
    """

    panels = GOAL_PANELS

    def __init__(self, trace: dict[str, Any], mission: str = "", focus: int | None = None):
        self.plt = plt = pyplot()
        self.trace = trace
        self.robots, self.goals = list(trace["robots"]), list(trace["goals"])
        self.poses = np.asarray(trace["poses"], dtype=float)
        self.belief = np.asarray(trace["goal_belief"], dtype=float)
        self.considered = np.asarray(trace["considered"], dtype=float)
        self.modelled = np.asarray(trace["modelled"], dtype=float)
        self.estimates = np.asarray(trace["estimates"], dtype=float)
        self.focus = focus_robot(trace) if focus is None else focus
        self.title = trace_title(trace, mission)
        n = len(self.robots)
        self.fig = fig = plt.figure(figsize=(13.0, 7.0))
        grid = fig.add_gridspec(
            3, 2, width_ratios=(1.0, 1.05), height_ratios=(1.0, 1.15, 0.75), wspace=0.28
        )
        self.map_axes = fig.add_subplot(grid[:, 0])
        self.belief_axes = fig.add_subplot(grid[0, 1])
        self.sets_axes = fig.add_subplot(grid[1, 1])
        self.events_axes = fig.add_subplot(grid[2, 1])
        goals = np.asarray(trace["goal_positions"], dtype=float).reshape(-1, 2)
        draw_obstacles(self.map_axes, trace.get("obstacles", []))
        self.goal_marks = draw_goals(self.map_axes, goals, self.goals, trace["success_radius"])
        self.closed = _closed_steps(trace)
        self.known = known_goals(trace)
        set_map_limits(self.map_axes, self.poses[:, :, :2], goals, trace["workspace"])
        ax = self.map_axes
        self.trails, self.discs, self.sensing = robot_artists(
            ax, self.robots, self.poses[0], trace.get("sensing_range")
        )
        colours = [robot_colour(i) for i in range(n)]
        self.estimate_marks = [
            [ax.plot([], [], "x-", color=colours[i], ms=7, lw=0.8, alpha=0.6,
                     gid=f"estimate:{a}->{b}")[0] for j, b in enumerate(self.robots) if j != i]
            for i, a in enumerate(self.robots)
        ]  # fmt: skip
        self.transient: list = []
        self._reading_setup()
        self._map_legend()
        self._belief_panel()
        self.knowing = self.belief_axes.text(
            1.03, 1.0, "", transform=self.belief_axes.transAxes, va="top", ha="left",
            fontsize=FONT_SIZE, family="monospace", gid="knowledge",
        )  # fmt: skip
        self._sets_panel()
        self.event_lines = event_panel(self.events_axes)
        self.heading = fig.suptitle("", fontsize=FONT_SIZE + 1)
        fig.text(0.44, 0.012, BELIEF_NOTE, fontsize=FONT_SIZE, va="bottom", ha="left",
                 color="0.3", gid="belief-note")  # fmt: skip
        fig.subplots_adjust(left=0.05, right=0.83, top=0.91, bottom=0.17, hspace=0.6)

    @staticmethod
    def mark_places(ax, trace: dict[str, Any], step: int) -> None:
        """The goals on the map ``ax`` as they are at ``step`` (closed ones hollow)."""
        goals = np.asarray(trace["goal_positions"], dtype=float).reshape(-1, 2)
        closed = _closed_steps(trace)
        shut = closed[min(step, len(closed) - 1)]
        draw_goals(ax, goals, trace["goals"], trace["success_radius"], shut)

    @staticmethod
    def status(trace: dict[str, Any], robot: int) -> str:
        """What ``robot`` did at the trace's last decision: the goal it headed for."""
        focal = trace["focal"]
        goal = int(focal[-1][robot][robot]) if len(focal) else -1
        return f"heading for {trace['goals'][goal] if goal >= 0 else '-'}"

    def _map_legend(self) -> None:
        from matplotlib.lines import Line2D

        extra = [
            Line2D([], [], marker="*", color="k", ls="", ms=12, label="goal"),
            Line2D([], [], marker="x", color="0.3", ls="", label="where a robot places a teammate"),
        ]
        if self.sensing:
            extra.append(Line2D([], [], ls="--", color="0.3", label="sensing radius"))
        self.map_axes.legend(
            handles=[*self.discs, *extra],
            fontsize=FONT_SIZE,
            loc="upper left",
            bbox_to_anchor=(-0.02, -0.08),
            ncol=3,
            frameon=False,
        )

    def _belief_panel(self) -> None:
        ax, n, m = self.belief_axes, len(self.robots), len(self.goals)
        self.belief_image = ax.imshow(
            np.zeros((n, m)), cmap="Greys", vmin=0, vmax=1, aspect="auto", interpolation="nearest"
        )
        ax.set_xticks(np.arange(m), self.goals if m <= 12 else [""] * m, fontsize=FONT_SIZE)
        ax.set_yticks(np.arange(n), self.robots, fontsize=FONT_SIZE)
        for i, label in enumerate(ax.get_yticklabels()):
            label.set_color(robot_colour(i))
            label.set_fontweight("bold")
        ax.set_title("each robot's belief that a goal is its own", fontsize=FONT_SIZE, loc="left")
        small = n * m <= 48
        self.belief_numbers = [
            [ax.text(g, i, "", ha="center", va="center", fontsize=FONT_SIZE) for g in range(m)]
            for i in range(n)
        ] if small else []  # fmt: skip

    def _sets_panel(self) -> None:
        from matplotlib.transforms import offset_copy

        ax, f = self.sets_axes, self.focus
        steps = np.arange(len(self.considered))
        lines = [(self.considered[:, i], i, "-", name) for i, name in enumerate(self.robots)]
        if len(self.modelled):
            lines += [
                (self.modelled[:, f, j], j, "--", f"{self.robots[f]}'s model of {name}'s")
                for j, name in enumerate(self.robots)
                if j != f
            ]
        for q, (values, i, style, label) in enumerate(lines):
            # each line SETS_GAP points from the next (own above, models below): lines of
            # equal values lie side by side rather than on one another
            shift = offset_copy(ax.transData, fig=self.fig, units="points",
                                y=(len(lines) - 1 - 2 * q) * SETS_GAP / 2)  # fmt: skip
            ax.plot(steps, values, style, color=robot_colour(i), lw=1.8, label=label,
                    transform=shift, gid=f"sets:{label}")  # fmt: skip
            ax.update_datalim(np.column_stack([steps, values]))  # shifted: not autoscaled
        ax.margins(y=0.12)  # room for the shifted lines at the top
        ax.autoscale_view()
        if len(self.considered) and np.nanmax(self.considered) > 20:
            ax.set_yscale("log")
        else:
            ax.set_ylim(bottom=0)
        ax.set_ylabel("configurations", fontsize=FONT_SIZE)
        ax.set_xlabel("step", fontsize=FONT_SIZE)
        ax.tick_params(labelsize=FONT_SIZE)
        ax.set_title(
            f"configuration sets: own (solid), {self.robots[f]}'s model of each teammate's "
            f"(dashed)\nequal values drawn {SETS_GAP:g} pt apart, own above",
            fontsize=FONT_SIZE,
            loc="left",
        )
        ax.legend(fontsize=FONT_SIZE, loc="upper left", bbox_to_anchor=(1.01, 1.05), frameon=False)
        self.cursor = ax.axvline(0, color="0.4", lw=0.8)

    def draw(self, step: int, since: int | None = None) -> list:
        """Show ``step`` (events of steps after ``since`` ringed on the map); the artists."""
        for artist in self.transient:
            artist.remove()
        self.transient.clear()
        pose, ax = self.poses[step], self.map_axes
        decided = min(step, len(self.belief) - 1)
        move_robots(self, step)
        for i in range(len(self.robots)):
            dx, dy = 1.2 * np.cos(pose[i, 2]), 1.2 * np.sin(pose[i, 2])
            self.transient.append(
                ax.arrow(pose[i, 0], pose[i, 1], dx, dy, width=0.12, color=robot_colour(i))
            )
        set_closed(self.goal_marks, self.closed[min(step, len(self.closed) - 1)])
        if decided >= 0:
            self._draw_estimates(decided, pose)
            self._draw_belief(decided)
            self._draw_reading(decided)
            self.knowing.set_text(self.knowledge_text(decided))
        self._draw_events(step, step - 1 if since is None else since)
        self.cursor.set_xdata([decided, decided])
        self.heading.set_text(f"{self.title}   step {step}")
        return [*self.trails, *self.discs, *self.transient, self.heading]

    def _reading_setup(self) -> None:
        """What one robot reads of its teammates' behaviour (teammate models), if kept: the
        focus robot, or else the first robot that kept them."""
        self.reading = None
        if "teammate_types" not in self.trace:
            return
        self.types = np.asarray(self.trace["teammate_types"], dtype=float)  # (T, n, n, K)
        kept = [i for i in range(self.types.shape[1]) if np.isfinite(self.types[:, i]).any()]
        if not kept:
            return
        self.reader = self.focus if self.focus in kept else kept[0]
        self.reading = self.sets_axes.text(
            1.01, -0.3, "", transform=self.sets_axes.transAxes, va="top", ha="left",
            fontsize=FONT_SIZE, family="monospace", gid="reading",
        )  # fmt: skip

    def _draw_reading(self, step: int) -> None:
        if self.reading is None:
            return
        names, prior = self.trace["types"], TYPE_PRIOR[0] if len(TYPE_PRIOR) else 0.0
        lines = [
            f"{self.robots[self.reader]} reads each",
            "teammate as (likeliest",
            "behaviour, posterior;",
            f"prior: {names[0]} {prior:.2f}):",
        ]
        shown = []
        for j, name in enumerate(self.robots):
            row = self.types[step, self.reader, j]
            if j != self.reader and np.isfinite(row).all():
                k = int(np.argmax(row))
                lines.append(f"{name} {names[k]} {row[k]:.2f}")
                shown.append(names[k])
        for name in dict.fromkeys(shown):  # what each behaviour shown means
            lines += textwrap.wrap(f"{name}: {TYPE_MEANINGS.get(name, name)}", 23,
                                   subsequent_indent=" ")  # fmt: skip
        self.reading.set_text("\n".join(lines))

    def _draw_estimates(self, step: int, pose: np.ndarray) -> None:
        for i, marks in enumerate(self.estimate_marks):
            others = [j for j in range(len(self.robots)) if j != i]
            for mark, j in zip(marks, others, strict=True):
                x, y = self.estimates[step, i, j]
                if np.isfinite(x) and np.isfinite(y):
                    mark.set_data([x, pose[j, 0]], [y, pose[j, 1]])
                    mark.set_markevery([0])
                else:
                    mark.set_data([], [])

    def _draw_belief(self, step: int) -> None:
        values = self.belief[step]
        self.belief_image.set_data(np.nan_to_num(values))
        computed = np.nansum(values, axis=1) > 0  # a robot not consulted has no belief
        for i, row in enumerate(self.belief_numbers):
            for g, text in enumerate(row):
                value = values[i, g]
                if not computed[i]:
                    text.set_text("n/c")
                elif self.known is not None and not self.known[step, i, i, g]:
                    text.set_text("·")
                else:
                    text.set_text("" if not np.isfinite(value) else f"{value:.2f}")
                text.set_color("w" if computed[i] and np.isfinite(value) and value > 0.55 else "k")

    def knowledge_text(self, step: int) -> str:
        """What each robot knows of at ``step`` and what the focus robot takes each teammate
        not to know of (every goal known to all without the trace's ``knows``)."""
        if self.known is None:
            return "every goal known\nto every robot"
        lines = ["knows of:"]
        for i, name in enumerate(self.robots):
            own = [g for g, k in zip(self.goals, self.known[step, i, i], strict=True) if k]
            lines.append(f"{name} {' '.join(own) or '-'}")
        f = self.focus
        for j, name in enumerate(self.robots):
            hidden = self.known[step, f, f] & ~self.known[step, f, j]
            if j != f and hidden.any():
                goals = " ".join(g for g, h in zip(self.goals, hidden, strict=True) if h)
                lines.append(f"{self.robots[f]}: {name} does\n  not know of {goals}")
        return "\n".join(lines)

    def _draw_events(self, step: int, since: int) -> None:
        self.transient += draw_events(self, step, since)

    def close(self) -> None:
        """Release the figure."""
        self.plt.close(self.fig)


def _closed_steps(trace: dict[str, Any]) -> np.ndarray:
    """``(T + 1, m)`` the goals closed at each step, from the trace's ``closed`` changes."""
    steps, m = int(trace["steps"]), len(trace["goals"])
    out = np.zeros((steps + 1, m), dtype=bool)
    for step, g, shut in sorted(trace.get("closed", [])):
        out[step:, g] = bool(shut)
    return out


#: The frames, each drawing the map and the panels it names (``panels``).
FRAMES = (TraceFrame, JointFrame)


def frame_for(trace: dict[str, Any], mission: str = "") -> TraceFrame | JointFrame:
    """The animation's figure over ``trace``: the frame drawing its kind's panels.

    Examples
    --------
    >>> from epistemica.sim import simulate
    >>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
    >>> from epistemica.sim.study.trace import trial_trace
    >>> s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1).replace(max_steps=4)
    >>> frame = frame_for(trial_trace(s, simulate(s, "third", seed=1)))
    >>> type(frame).__name__, frame.panels == s.kind.panels
    ('JointFrame', True)
    >>> frame.close()
    """
    return frame_type(trace)(trace, mission)


def frame_type(trace: dict[str, Any]) -> type[TraceFrame] | type[JointFrame]:
    """The frame class drawing the panels of ``trace``'s kind (its ``mark_places`` and
    ``status`` also serve the trajectory figure and ``simulate``'s text).

    Examples
    --------
    >>> frame_type({"format": "epistemica-trace", "kind": "collaborative"}).__name__
    'JointFrame'
    """
    panels = kind_of_trace(trace).panels
    frame = next((f for f in FRAMES if f.panels == panels), None)
    if frame is None:  # a kind added without its drawing
        raise EpistemicaError(f"no figure draws the panels {', '.join(panels)}")
    return frame
