"""Pictures of a trial: trajectories (PNG) and an animation with each robot's belief (GIF).

matplotlib is imported only here, with the Agg backend (no display needed); without it
the functions raise an :class:`~epistemica.del_.errors.EpistemicaError` naming the extra
to install (``pip install 'epistemica[plot]'``). GIFs are written by Pillow.

In the animation, the map shows every robot (a disc, an arrow for its heading, a fading
trail) and every goal (a star with its success radius); beside it, one row of bars per
robot shows that robot's belief about its own goal (the marginal of its belief over
configurations, one bar per goal, coloured like the goal). A bar chart at 1.0 on one goal
is certainty; flat bars are indifference.
"""

from __future__ import annotations

import numpy as np

from epistemica.del_.errors import EpistemicaError
from epistemica.sim.scenario import Scenario
from epistemica.sim.trial import Trial

__all__ = ["animate_trial", "plot_trial", "pyplot"]

_ROBOT_COLOURS = "tab10"
_MAX_FRAMES = 60


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


def _title(scenario: Scenario, trial: Trial) -> str:
    outcome = f"success at step {trial.steps}" if trial.success else f"failed ({trial.steps} steps)"
    levels = ", ".join(dict.fromkeys(trial.policies))
    return f"{scenario.mission}, {scenario.n_robots} robots, {levels}, seed {trial.seed}: {outcome}"


def _draw_goals(ax, scenario: Scenario, goal_colours) -> None:
    for g, (x, y) in enumerate(scenario.goals):
        ax.add_patch(_circle((x, y), scenario.success_radius, goal_colours[g], alpha=0.15))
        ax.plot(x, y, marker="*", markersize=14, color=goal_colours[g], markeredgecolor="k")
        ax.annotate(f"g{g}", (x, y), textcoords="offset points", xytext=(6, 6), fontsize=8)


def _circle(centre, radius, colour, alpha):
    from matplotlib.patches import Circle

    return Circle(centre, radius, color=colour, alpha=alpha, linewidth=0)


def _limits(ax, scenario: Scenario, trial: Trial) -> None:
    pts = np.concatenate([trial.trajectory[:, :, :2].reshape(-1, 2), scenario.goals])
    low = np.minimum(pts.min(axis=0), 0.0) - 1
    high = np.maximum(pts.max(axis=0), scenario.workspace) + 1
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _colours(plt, count: int):
    cmap = plt.get_cmap(_ROBOT_COLOURS)
    return [cmap(i % 10) for i in range(count)]


def plot_trial(scenario: Scenario, trial: Trial, path) -> None:
    """Write the trajectories of ``trial`` in ``scenario`` as a PNG at ``path``.

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
    robots, goals = _colours(plt, scenario.n_robots), _colours(plt, scenario.n_goals)
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    _draw_goals(ax, scenario, ["0.45"] * scenario.n_goals if scenario.n_goals > 10 else goals)
    for i in range(scenario.n_robots):
        path_i = trial.trajectory[:, i]
        label = f"r{i} ({scenario.sensors[i]}, {trial.policies[i]})"
        ax.plot(path_i[:, 0], path_i[:, 1], "-", color=robots[i], linewidth=1.6, label=label)
        ax.plot(*path_i[0, :2], "o", color=robots[i], markeredgecolor="k")
        ax.plot(*path_i[-1, :2], "s", color=robots[i], markeredgecolor="k")
    _limits(ax, scenario, trial)
    ax.set_title(_title(scenario, trial), fontsize=9)
    ax.legend(fontsize=7, loc="upper right", title="o start, ■ end", title_fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def animate_trial(scenario: Scenario, trial: Trial, path, fps: int = 6) -> int:
    """Write an animated GIF of ``trial``: the map and each robot's belief as bars.

    At most 60 frames (steps are subsampled evenly, the last one always shown). Returns
    the number of frames.

    Examples
    --------
    >>> import os, tempfile
    >>> from epistemica.sim import Scenario, simulate
    >>> s = Scenario.paper("allocation", 2, seed=0).replace(max_steps=6)
    >>> animate_trial(s, simulate(s, "third", seed=0), os.path.join(tempfile.mkdtemp(), "t.gif"))
    7
    """
    plt = pyplot()
    from matplotlib.animation import FuncAnimation, PillowWriter

    n, m = scenario.n_robots, scenario.n_goals
    robots, goals = _colours(plt, n), _colours(plt, m)
    frames = np.unique(np.linspace(0, trial.steps, min(trial.steps + 1, _MAX_FRAMES)).astype(int))
    fig = plt.figure(figsize=(9.6, 5.0))
    grid = fig.add_gridspec(n, 2, width_ratios=(1.25, 1.0), wspace=0.25, hspace=0.6)
    ax = fig.add_subplot(grid[:, 0])
    bars_axes = [fig.add_subplot(grid[i, 1]) for i in range(n)]
    _draw_goals(ax, scenario, goals if m <= 10 else ["0.45"] * m)
    _limits(ax, scenario, trial)
    trails = [ax.plot([], [], "-", color=robots[i], linewidth=1.2, alpha=0.7)[0] for i in range(n)]
    discs = [
        ax.plot([], [], "o", color=robots[i], markeredgecolor="k", markersize=9)[0]
        for i in range(n)
    ]
    arrows = []
    bars = []
    for i, bax in enumerate(bars_axes):
        bars.append(bax.bar(np.arange(m), np.zeros(m), color=goals if m <= 10 else "0.45"))
        bax.set_ylim(0, 1)
        bax.set_yticks([0, 1])
        bax.set_xticks(np.arange(m) if m <= 10 else [])
        bax.set_xticklabels([f"g{g}" for g in range(m)] if m <= 10 else [], fontsize=7)
        bax.tick_params(labelsize=7)
        bax.set_ylabel(f"r{i}", color=robots[i], rotation=0, labelpad=12, fontsize=9)
    bars_axes[0].set_title("each robot's belief about its own goal", fontsize=9)
    title = ax.set_title("", fontsize=9)

    def draw(step: int):
        for arrow in arrows:
            arrow.remove()
        arrows.clear()
        pose = trial.trajectory[step]
        for i in range(n):
            trails[i].set_data(
                trial.trajectory[: step + 1, i, 0], trial.trajectory[: step + 1, i, 1]
            )
            discs[i].set_data([pose[i, 0]], [pose[i, 1]])
            arrows.append(
                ax.arrow(
                    pose[i, 0],
                    pose[i, 1],
                    1.2 * np.cos(pose[i, 2]),
                    1.2 * np.sin(pose[i, 2]),
                    width=0.12,
                    color=robots[i],
                )
            )
            belief = trial.goal_belief[min(step, trial.steps - 1), i] if trial.steps else ()
            for bar, height in zip(bars[i], belief, strict=False):
                bar.set_height(height)
        title.set_text(f"{_title(scenario, trial)}\nstep {step}")
        return [*trails, *discs, *arrows, title]

    animation = FuncAnimation(fig, draw, frames=frames, blit=False)
    animation.save(path, writer=PillowWriter(fps=fps), dpi=80)
    plt.close(fig)
    return len(frames)
