"""Pictures of a trial: trajectories (PNG) and an animation of what each robot knows (GIF).

matplotlib is imported only here, with the Agg backend (no display needed); without it
the functions raise an :class:`~epistemica.del_.errors.EpistemicaError` naming the extra
to install (``pip install 'epistemica[plot]'``). GIFs are written by Pillow.

The animation is drawn from a trial's trace (:mod:`epistemica.sim.study.trace`), so a stored
trace draws the same picture as the trial itself. Goals and robots cannot be confused:
goals are black stars (their success radius a grey disc), labelled with the mission's
names; robots take a qualitative palette without grey. The map shows each robot (disc,
heading, trail), its sensing radius (dashed circle), where it places each teammate (a
cross in the estimating robot's colour, joined to the teammate's true position) and
rings around the robots that observed an event at that moment. Beside the map: each
robot's belief about its own goal (a grey-scale table, robots by goals), the size of each
robot's configuration set over time (solid) with one robot's model of each teammate's set
(dashed, the teammate's colour; the robot whose model differs most from the truth), and
the events observed so far with their observers.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from epistemica.del_.errors import EpistemicaError
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.trial import Trial
from epistemica.sim.study.palette import ROBOT_COLOURS, focus_robot, robot_colour
from epistemica.sim.study.trace import trial_trace

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

_MAX_FRAMES = 60
FONT_SIZE = 10
_EVENT_LINES = 6
_GIF_DPI = 72


def pyplot():
    """matplotlib's pyplot on the Agg backend, or a clear error without the plot extra."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:
        raise EpistemicaError(
            "figures need matplotlib",
            hint="install the plot extra: pip install 'epistemica[plot]'",
        ) from exc
    return plt


def save_figure(fig, path, fmt: str | None = None) -> None:
    """Write ``fig`` to exactly ``path`` in format ``fmt`` (default: the path's extension
    among png, pdf and svg, else png), 100 dpi. Unlike a bare ``savefig``, no extension
    is appended to a path without one, and a write that fails (a full disk, a device)
    is an :class:`EpistemicaError` naming the file, never a success reported elsewhere.
    """
    if fmt is None:
        suffix = str(path).rsplit(".", 1)[-1].lower() if "." in str(path) else ""
        fmt = suffix if suffix in ("png", "pdf", "svg") else "png"
    try:
        fig.savefig(path, dpi=100, format=fmt)
    except OSError as err:
        raise _unwritable("figure", path, err) from err


def _unwritable(what: str, path, err: OSError) -> EpistemicaError:
    return EpistemicaError(
        f"cannot write the {what} {path}: {err.strerror or err}",
        hint="write it to a folder that exists, is writable and has room",
    )


def _title(scenario: Scenario, trial: Trial) -> str:
    outcome = f"success at step {trial.steps}" if trial.success else f"failed ({trial.steps} steps)"
    levels = ", ".join(dict.fromkeys(trial.policies))
    return f"{scenario.mission}, {scenario.n_robots} robots, {levels}, seed {trial.seed}: {outcome}"


def trace_title(trace: dict[str, Any], mission: str = "") -> str:
    steps = trace["steps"]
    outcome = f"success at step {steps}" if trace["success"] else f"failed ({steps} steps)"
    levels = ", ".join(dict.fromkeys(trace["policies"]))
    head = f"{mission}, " if mission else ""
    return f"{head}{len(trace['robots'])} robots, {levels}, seed {trace['seed']}: {outcome}"


def draw_goals(ax, goals: np.ndarray, names, radius: float) -> None:
    from matplotlib.patches import Circle

    for (x, y), name in zip(goals, names, strict=True):
        ax.add_patch(Circle((x, y), radius, color="0.8", alpha=0.5, linewidth=0, gid="goal-area"))
        ax.plot(x, y, marker="*", markersize=15, color="k", markeredgecolor="w", gid=f"goal:{name}")
        ax.annotate(
            name,
            (x, y),
            textcoords="offset points",
            xytext=(7, 5),
            fontsize=FONT_SIZE,
            weight="bold",
        )


def set_map_limits(ax, positions: np.ndarray, goals: np.ndarray, workspace: float) -> None:
    pts = np.concatenate([positions.reshape(-1, 2), goals.reshape(-1, 2)])
    pts = pts[np.isfinite(pts).all(axis=1)]
    low = np.minimum(pts.min(axis=0), 0.0) - 1
    high = np.maximum(pts.max(axis=0), workspace) + 1
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)", fontsize=FONT_SIZE)
    ax.set_ylabel("y (m)", fontsize=FONT_SIZE)
    ax.tick_params(labelsize=FONT_SIZE)


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
    draw_goals(ax, scenario.goals, scenario.goal_names, scenario.success_radius)
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


def _event_text(event: list, robots: list[str]) -> str:
    # Version 1 traces gave arguments as bare indices (robot or goal unsaid): name only.
    step, name, arguments, observers = event
    named = [a for a in arguments if isinstance(a, str) and a]
    about = f"({', '.join(named)})" if named else ""
    seen = ", ".join(robots[o] for o in observers) or "nobody"
    return f"step {step}: {name}{about}, seen by {seen}"


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
        draw_goals(self.map_axes, goals, self.goals, trace["success_radius"])
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
                ax.plot(
                    steps,
                    self.modelled[:, f, j],
                    "--",
                    color=robot_colour(j),
                    lw=1.4,
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
            "configuration sets: own (solid), nested (dashed)", fontsize=FONT_SIZE, loc="left"
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
        if decided >= 0:
            self._draw_estimates(decided, pose)
            self._draw_belief(decided)
            self._draw_reading(decided)
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
        lines = [f"{self.robots[self.reader]} reads its teammates as:"]
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
        for i, row in enumerate(self.belief_numbers):
            for g, text in enumerate(row):
                value = values[i, g]
                text.set_text("" if not np.isfinite(value) else f"{value:.2f}")
                text.set_color("w" if np.isfinite(value) and value > 0.55 else "k")

    def _draw_events(self, step: int, since: int) -> None:
        self.transient += draw_events(self, step, since)

    def close(self) -> None:
        """Release the figure."""
        self.plt.close(self.fig)


def robot_artists(ax, robots: list[str], start: np.ndarray, sensing_range: float | None):
    """``(trails, discs, sensing circles)`` of ``robots`` on ``ax``, the circles (none
    without a sensing range) centred on their ``start`` places."""
    from matplotlib.patches import Circle

    colours = [robot_colour(i) for i in range(len(robots))]
    trails = [ax.plot([], [], "-", color=c, lw=1.3, alpha=0.7)[0] for c in colours]
    discs = [
        ax.plot([], [], "o", color=c, mec="k", ms=10, label=name, gid=f"robot:{name}")[0]
        for name, c in zip(robots, colours, strict=True)
    ]
    circles = []
    for i, name in enumerate(robots if sensing_range is not None else []):
        circle = Circle(tuple(start[i, :2]), sensing_range, fill=False, ls="--", lw=1.0,
                        ec=colours[i], gid=f"sensing:{name}")  # fmt: skip
        ax.add_patch(circle)
        circles.append(circle)
    return trails, discs, circles


def move_robots(frame, step: int) -> None:
    """Put ``frame``'s trails, discs and sensing circles (:func:`robot_artists`) at
    ``step`` of ``frame.poses``."""
    pose = frame.poses[step]
    for i in range(len(frame.robots)):
        frame.trails[i].set_data(frame.poses[: step + 1, i, 0], frame.poses[: step + 1, i, 1])
        frame.discs[i].set_data([pose[i, 0]], [pose[i, 1]])
        if frame.sensing:
            frame.sensing[i].center = (pose[i, 0], pose[i, 1])


def event_panel(ax):
    """Turn ``ax`` into the list of events observed; its text (see :func:`draw_events`)."""
    ax.axis("off")
    ax.set_title("events observed (and by whom)", fontsize=FONT_SIZE, loc="left")
    return ax.text(0.0, 1.0, "", va="top", ha="left", fontsize=FONT_SIZE, family="monospace")


def draw_events(frame, step: int, since: int) -> list:
    """List the events of ``frame.trace`` up to ``step`` in ``frame.event_lines`` and ring,
    on ``frame.map_axes``, the observers of those after ``since``; the rings."""
    events = [e for e in frame.trace["events"] if e[0] <= step]
    lines = [_event_text(e, frame.robots) for e in events[-_EVENT_LINES:]]
    more = len(events) - len(lines)
    head = [f"... {more} earlier"] if more > 0 else []
    frame.event_lines.set_text("\n".join(head + lines) if events else "(none yet)")
    rings = []
    for event in (e for e in events if e[0] > since):
        for o in event[3]:
            ring = frame.map_axes.plot(
                *frame.poses[step, o, :2],
                "o",
                ms=22,
                mfc="none",
                mec=robot_colour(o),
                mew=2.5,
                gid=f"event:{event[1]}",
            )
            rings.append(ring[0])  # fmt: skip
    return rings


def animate_trace(trace: dict[str, Any], path, fps: int = 6, mission: str = "") -> int:
    """Write an animated GIF of a trial's trace (see the module docstring); the frame count.

    At most 60 frames (steps subsampled evenly, the first and last always shown); an event
    is ringed in the frame that first shows its step.
    """
    return write_gif(TraceFrame(trace, mission), int(trace["steps"]), path, fps)


def write_gif(frame, steps: int, path, fps: int = 6) -> int:
    """Write ``frame`` (an object with ``fig``, ``draw(step, since)`` and ``close()``) at
    most 60 steps of ``0..steps`` as an animated GIF, closing it; the frame count."""
    from PIL import Image

    frames = np.unique(np.linspace(0, steps, min(steps + 1, _MAX_FRAMES)).astype(int))
    images = []
    try:
        frame.fig.set_dpi(_GIF_DPI)
        since = -1
        for step in frames:
            frame.draw(int(step), since)
            since = int(step)
            frame.fig.canvas.draw()  # one render per frame (FuncAnimation renders twice)
            rgb = Image.fromarray(np.asarray(frame.fig.canvas.buffer_rgba())[:, :, :3])
            # One palette for every frame (the first frame's: every robot, goal and panel
            # is drawn there): Pillow's frame differences compare palette indices, and
            # per-frame palettes made unchanged parts of later frames lose their colours.
            palette = images[0] if images else rgb.quantize(colors=255, dither=Image.Dither.NONE)
            images.append(rgb.quantize(palette=palette, dither=Image.Dither.NONE))
    finally:
        frame.close()
    try:
        images[0].save(
            path, "GIF", save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0
        )
    except OSError as err:
        raise _unwritable("animation", path, err) from err
    return len(frames)


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
