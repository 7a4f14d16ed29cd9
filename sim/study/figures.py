"""Pictures of a trial: trajectories (PNG) and an animation of what each robot knows (GIF).

matplotlib is imported only when drawing (:mod:`epistemica.sim.study.figure_parts`, the shared
drawing parts), with the Agg backend (no display needed); without it the functions raise an
:class:`~epistemica.del_.errors.EpistemicaError` naming the extra to install (``pip install
'epistemica[plot]'``). GIFs are written by Pillow.

The animation is drawn from a trial's trace (:mod:`epistemica.sim.study.trace`), so a stored
trace draws the same picture as the trial itself. Goals and robots cannot be confused:
goals are black stars (their success radius a grey disc), labelled with the mission's
names; robots take a qualitative palette without grey. The map shows each robot (disc,
heading, trail), its sensing radius (dashed circle), where it places each teammate (a
cross in the estimating robot's colour, joined to the teammate's true position) and
rings around the robots that observed an event at that moment; obstacles are dark
polygons, a closed goal a hollow star. Beside the map: each robot's belief about its own
goal (a grey-scale table, robots by goals; ``n/c`` where it was not computed, ``·`` on a goal
the robot does not know of), what each robot knows of (and what the focus robot takes each
teammate not to know of), the size of each robot's configuration set over time (solid) with
the focus robot's model of each teammate's set (dashed, the teammate's colour), and the
events observed so far with their observers.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.trial import Trial
from epistemica.sim.study.figure_parts import (
    FONT_SIZE,
    draw_events,
    draw_goals,
    draw_obstacles,
    event_panel,
    move_robots,
    pyplot,
    robot_artists,
    save_figure,
    set_closed,
    set_map_limits,
    write_gif,
)
from epistemica.sim.study.palette import ROBOT_COLOURS, focus_robot, robot_colour
from epistemica.sim.study.trace import known_goals, trial_trace

__all__ = [
    "FONT_SIZE",
    "ROBOT_COLOURS",
    "TraceFrame",
    "animate_trace",
    "animate_trial",
    "draw_events",
    "draw_goals",
    "event_panel",
    "focus_robot",
    "move_robots",
    "plot_trial",
    "pyplot",
    "robot_artists",
    "save_figure",
    "set_map_limits",
    "trace_title",
    "write_gif",
]


def _title(scenario: Scenario, trial: Trial) -> str:
    outcome = (
        f"succeeded at step {trial.steps}"
        if trial.success
        else f"failed within {trial.steps} steps"
    )
    levels = ", ".join(dict.fromkeys(trial.policies))
    return f"{scenario.mission}, {scenario.n_robots} robots, {levels}, seed {trial.seed}: {outcome}"


def trace_title(trace: dict[str, Any], mission: str = "") -> str:
    steps = trace["steps"]
    outcome = f"succeeded at step {steps}" if trace["success"] else f"failed within {steps} steps"
    levels = ", ".join(dict.fromkeys(trace["policies"]))
    head = f"{mission}, " if mission else ""
    return f"{head}{len(trace['robots'])} robots, {levels}, seed {trace['seed']}: {outcome}"


def plot_trial(scenario: Scenario, trial: Trial, path) -> None:
    """Write the trajectories of ``trial`` in ``scenario`` as a figure at ``path`` (the
    extension picks the format: ``.png``, ``.pdf``, ``.svg``).

    Examples
    --------
    >>> import os, tempfile
    >>> from epistemica.sim import Scenario, simulate
    >>> s = Scenario.paper("rendezvous", 2, 2, seed=0)
    >>> path = os.path.join(tempfile.mkdtemp(), "t.png")
    >>> plot_trial(s, simulate(s, "convention", seed=0), path)
    >>> os.path.getsize(path) > 10_000
    True
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    draw_obstacles(ax, scenario.obstacles)
    closed = scenario.closed if trial.closed_goals is None else trial.closed_goals[-1]
    draw_goals(ax, scenario.goals, scenario.goal_names, scenario.success_radius, closed)
    for i, name in enumerate(scenario.robot_names):
        path_i = trial.trajectory[:, i]
        colour = robot_colour(i)
        label = f"{name} ({scenario.sensors[i]}, {trial.policies[i]})"
        ax.plot(path_i[:, 0], path_i[:, 1], "-", color=colour, linewidth=1.6, label=label)
        ax.plot(*path_i[0, :2], "o", color=colour, markeredgecolor="k")
        ax.plot(*path_i[-1, :2], "s", color=colour, markeredgecolor="k")
    set_map_limits(ax, trial.trajectory[:, :, :2], scenario.goals, scenario.workspace)
    ax.set_title(_title(scenario, trial), fontsize=FONT_SIZE)
    ax.legend(
        fontsize=FONT_SIZE, loc="upper right", title="o start, ■ end", title_fontsize=FONT_SIZE
    )
    fig.tight_layout()
    save_figure(fig, path, "png")
    plt.close(fig)


class TraceFrame:
    """The animation's figure over a trace; :meth:`draw` shows one step.

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
            [
                ax.plot(
                    [],
                    [],
                    "x-",
                    color=colours[i],
                    ms=7,
                    lw=0.8,
                    alpha=0.6,
                    gid=f"estimate:{a}->{b}",
                )[0]
                for j, b in enumerate(self.robots)
                if j != i
            ]
            for i, a in enumerate(self.robots)
        ]
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
        fig.subplots_adjust(left=0.05, right=0.83, top=0.91, bottom=0.17, hspace=0.6)

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
        ax, f = self.sets_axes, self.focus
        steps = np.arange(len(self.considered))
        for i, name in enumerate(self.robots):
            ax.plot(steps, self.considered[:, i], "-", color=robot_colour(i), lw=1.8, label=name)
        for j, name in enumerate(self.robots):
            if j != f and len(self.modelled):
                ax.plot(  # wide and pale under the solid lines: visible where they agree
                    steps,
                    self.modelled[:, f, j],
                    "--",
                    color=robot_colour(j),
                    lw=4.0,
                    alpha=0.45,
                    zorder=1,
                    label=f"{self.robots[f]}'s model of {name}'s",
                )
        if len(self.considered) and np.nanmax(self.considered) > 20:
            ax.set_yscale("log")
        else:
            ax.set_ylim(bottom=0)
        ax.set_ylabel("configurations", fontsize=FONT_SIZE)
        ax.set_xlabel("step", fontsize=FONT_SIZE)
        ax.tick_params(labelsize=FONT_SIZE)
        ax.set_title(
            f"configuration sets: own (solid), {self.robots[f]}'s model of each teammate's "
            "(dashed)",
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
        lines = [
            f"{self.robots[self.reader]}'s read of its",
            "teammates' behaviour",
            "(posterior):",
        ]
        for j, name in enumerate(self.robots):
            row = self.types[step, self.reader, j]
            if j != self.reader and np.isfinite(row).all():
                k = int(np.argmax(row))
                lines.append(f"{name} {self.trace['types'][k]} {row[k]:.2f}")
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


def animate_trace(trace: dict[str, Any], path, fps: int = 6, mission: str = "") -> int:
    """Write an animated GIF of a trial's trace (see the module docstring); the frame count.

    At most 60 frames (steps subsampled evenly, the first and last always shown); an event
    is ringed in the frame that first shows its step.
    """
    return write_gif(TraceFrame(trace, mission), int(trace["steps"]), path, fps)


def animate_trial(scenario: Scenario, trial: Trial, path, fps: int = 6) -> int:
    """Write an animated GIF of ``trial`` (see :func:`animate_trace`); the frame count.

    Examples
    --------
    >>> import os, tempfile
    >>> from epistemica.sim import Scenario, simulate
    >>> s = Scenario.paper("allocation", 2, seed=0).replace(max_steps=6)
    >>> animate_trial(s, simulate(s, "third", seed=0), os.path.join(tempfile.mkdtemp(), "t.gif"))
    7
    """
    pyplot()  # the clear error before any work
    return animate_trace(trial_trace(scenario, trial), path, fps, scenario.mission)
