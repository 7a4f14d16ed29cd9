"""The drawing parts the trial figures share: matplotlib on Agg, saving, the title, the map
(goals, closed goals, obstacles, limits and axes), robots and their sensing circles, a table
of robots by goals, the events panel, and GIF writing.

Used by :mod:`epistemica.sim.study.figures` (a trial's picture and animation, the panels of
every mission kind). matplotlib is imported only when drawing, with
the Agg backend (no display needed); without it :func:`pyplot` raises an
:class:`~epistemica.del_.errors.EpistemicaError` naming the extra to install. GIFs are
written by Pillow.

Examples
--------
>>> fig, ax = pyplot().subplots()
>>> draw_obstacles(ax, [[[0, 0], [1, 0], [1, 1]]])
1
>>> pyplot().close(fig)
"""

from __future__ import annotations

import numpy as np

from epistemica.del_.errors import EpistemicaError
from epistemica.sim.study.palette import robot_colour

__all__ = [
    "FONT_SIZE",
    "draw_events",
    "draw_goals",
    "draw_obstacles",
    "event_panel",
    "event_text",
    "move_robots",
    "pyplot",
    "robot_artists",
    "robot_table",
    "save_figure",
    "set_closed",
    "set_map_limits",
    "trace_title",
    "unwritable",
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
        raise unwritable("figure", path, err) from err


def unwritable(what: str, path, err: OSError) -> EpistemicaError:
    return EpistemicaError(
        f"cannot write the {what} {path}: {err.strerror or err}",
        hint="write it to a folder that exists, is writable and has room",
    )


def trace_title(trace: dict, mission: str = "") -> str:
    """The title of a trace's figure: mission, team size, levels, seed and outcome."""
    steps = trace["steps"]
    outcome = f"succeeded at step {steps}" if trace["success"] else f"failed within {steps} steps"
    levels = ", ".join(dict.fromkeys(trace["policies"]))
    head = f"{mission}, " if mission else ""
    return f"{head}{len(trace['robots'])} robots, {levels}, seed {trace['seed']}: {outcome}"


def robot_table(ax, names: list[str], robots, columns: list[str], title: str):
    """A grey table on ``ax``: one row per robot (``names``, coloured as ``robots``), one
    column per goal or task; its image (``set_data`` an array in 0..1.6, dark: more)."""
    image = ax.imshow(np.zeros((len(names), len(columns))), cmap="Greys", vmin=0, vmax=1.6,
                      aspect="auto", interpolation="nearest")  # fmt: skip
    ax.set_xticks(np.arange(len(columns)), columns, fontsize=FONT_SIZE)
    ax.set_yticks(np.arange(len(names)), names, fontsize=FONT_SIZE)
    for label, i in zip(ax.get_yticklabels(), robots, strict=True):
        label.set_color(robot_colour(i))
        label.set_fontweight("bold")
    ax.set_title(title, fontsize=FONT_SIZE, loc="left")
    return image


def draw_goals(ax, goals: np.ndarray, names, radius: float, closed=None) -> list:
    """Goals as black stars on grey discs (their success radius), named; a goal closed
    (``closed[g]``) a hollow star named "(closed)". The star and name artists per goal
    (:func:`set_closed` changes them)."""
    from matplotlib.patches import Circle

    marks = []
    for (x, y), name in zip(goals, names, strict=True):
        ax.add_patch(Circle((x, y), radius, color="0.8", alpha=0.5, linewidth=0, gid="goal-area"))
        star = ax.plot(x, y, marker="*", markersize=15, color="k", markeredgecolor="w",
                       gid=f"goal:{name}")[0]  # fmt: skip
        label = ax.annotate(
            name,
            (x, y),
            textcoords="offset points",
            xytext=(7, 5),
            fontsize=FONT_SIZE,
            weight="bold",
        )
        marks.append((star, label, name))
    if closed is not None:
        set_closed(marks, closed)
    return marks


def set_closed(marks: list, closed) -> None:
    """Draw the goals of ``marks`` (:func:`draw_goals`) closed where ``closed`` says."""
    for (star, label, name), shut in zip(marks, closed, strict=True):
        star.set_markerfacecolor("w" if shut else "k")
        star.set_markeredgecolor("k" if shut else "w")
        label.set_text(f"{name} (closed)" if shut else name)


def draw_obstacles(ax, polygons) -> int:
    """Obstacles (polygons, ``[[x, y], ...]`` each, m) as dark filled shapes; how many."""
    from matplotlib.patches import Polygon

    for k, points in enumerate(polygons):
        ax.add_patch(Polygon(np.asarray(points, dtype=float), closed=True, fc="0.45",
                             ec="0.2", alpha=0.7, gid=f"obstacle:{k}"))  # fmt: skip
    return len(polygons)


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


def event_text(event: list, robots: list[str]) -> str:
    # Version 1 traces gave arguments as bare indices (robot or goal unsaid): name only.
    step, name, arguments, observers = event
    named = [a for a in arguments if isinstance(a, str) and a]
    about = f"({', '.join(named)})" if named else ""
    seen = ", ".join(robots[o] for o in observers) or "nobody"
    return f"step {step}: {name}{about}, seen by {seen}"


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
    lines = [event_text(e, frame.robots) for e in events[-_EVENT_LINES:]]
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
        raise unwritable("animation", path, err) from err
    return len(frames)
