"""Summaries of sweep results: success with Wilson intervals, steps, completion, figures.

Examples
--------
>>> lo, hi = wilson_interval(45, 50)
>>> round(lo, 3), round(hi, 3)
(0.786, 0.957)
>>> rows = [{"mission": "rendezvous", "robots": 2, "goals": 2, "reasoning": "zero",
...          "options": "{}", "success": s, "steps": 10, "completion_step": None,
...          "decision_ms": 0.1, "considered": 1.0} for s in (1, 1, 0)]
>>> cell = summarise(rows)[0]
>>> cell.trials, cell.successes, cell.mean_steps
(3, 2, 10.0)
"""

from __future__ import annotations

import json
import math
import textwrap
from collections.abc import Iterable, Sequence
from typing import NamedTuple

import numpy as np

from epistemica.sim.kinds.registry import KINDS
from epistemica.sim.policies.levels import REASONING
from epistemica.sim.study.figures import pyplot, save_figure
from epistemica.sim.study.palette import level_style

__all__ = [
    "Cell",
    "disputed_seed",
    "format_table",
    "plot_levels",
    "plot_results",
    "study_order",
    "summarise",
    "trial_counts",
    "wilson_interval",
]

_Z95 = 1.959963984540054


def _tasks(mission: str) -> bool:
    """Whether a results row's mission is done task by task (completion, not success, is
    what tells its levels apart); an unknown name, from an older file, is not."""
    kind = KINDS.get(mission)
    return kind is not None and kind.tasks


def wilson_interval(successes: int, trials: int, z: float = _Z95) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95 % by default)."""
    if trials == 0:
        return 0.0, 1.0
    p = successes / trials
    centre = (p + z * z / (2 * trials)) / (1 + z * z / trials)
    half = (
        z * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials)) / (1 + z * z / trials)
    )
    return max(0.0, centre - half), min(1.0, centre + half)


class Cell(NamedTuple):
    """The trials of one (mission, robots, goals, level, options) cell."""

    mission: str
    robots: int
    goals: int
    reasoning: str
    options: str
    trials: int
    successes: int
    low: float
    high: float
    mean_steps: float
    mean_completion: float
    decision_ms: float
    considered: float
    unpruned: float = math.nan

    @property
    def rate(self) -> float:
        """Success rate in [0, 1]."""
        return self.successes / self.trials


def summarise(rows: Iterable[dict], step_limit_for_failures: int = 150) -> list[Cell]:
    """One :class:`Cell` per parameter combination, sorted.

    ``mean_steps`` is over successful trials (NaN if none); ``mean_completion`` (multitask)
    counts a failed trial as ``step_limit_for_failures``, as the published study did.
    """
    groups: dict[tuple, list[dict]] = {}
    for row in rows:
        key = (row["mission"], row["robots"], row["goals"], row["reasoning"], row["options"])
        groups.setdefault(key, []).append(row)
    cells = []
    for key, members in sorted(groups.items()):
        ok = [r for r in members if r["success"]]
        completion = [
            r["completion_step"] if r["completion_step"] is not None else step_limit_for_failures
            for r in members
        ]
        cells.append(
            Cell(
                *key,
                len(members),
                len(ok),
                *wilson_interval(len(ok), len(members)),
                float(np.mean([r["steps"] for r in ok])) if ok else math.nan,
                float(np.mean(completion)) if _tasks(key[0]) else math.nan,
                float(np.mean([r["decision_ms"] for r in members])),
                float(np.mean([r["considered"] for r in members])),
                _mean_unpruned(members),
            )
        )
    return cells


def disputed_seed(rows: Iterable[dict], levels: Sequence[str]) -> int | None:
    """The seed of the trial that shows what the highest level (the last of ``levels``)
    adds; None when the levels agree on every seed.

    In order of preference, the first seed where: the last level succeeds and the level
    before it fails (the extra reasoning decided); the last level succeeds and some other
    level fails; the levels disagree at all.

    Examples
    --------
    >>> rows = [{"seed": s, "reasoning": lv, "success": ok} for s, lv, ok in
    ...         [(0, "zero", 0), (0, "first", 1), (0, "third", 1),
    ...          (1, "zero", 0), (1, "first", 0), (1, "third", 1)]]
    >>> disputed_seed(rows, ["zero", "first", "third"])
    1
    >>> disputed_seed(rows[1:3], ["first", "third"]) is None
    True
    """
    outcomes: dict[int, dict[str, bool]] = {}
    for row in rows:
        if row["reasoning"] in levels:
            outcomes.setdefault(int(row["seed"]), {})[row["reasoning"]] = bool(row["success"])
    complete = {s: o for s, o in sorted(outcomes.items()) if len(o) == len(set(levels))}
    last, below = levels[-1], levels[-2] if len(levels) > 1 else None
    rules = (
        lambda o: o[last] and below is not None and not o[below],
        lambda o: o[last] and not all(o.values()),
        lambda o: len(set(o.values())) > 1,
    )
    for rule in rules:
        for seed, seen in complete.items():
            if rule(seen):
                return seed
    return None


def study_order(levels: Iterable[str]) -> list[str]:
    """Level names in the order of the study (:data:`~epistemica.sim.policies.levels.REASONING`:
    from no reasoning to the highest order), unknown names last in their given order.

    Examples
    --------
    >>> study_order(["third", "convention", "zero", "first"])
    ['zero', 'convention', 'first', 'third']
    """
    rank = {name: i for i, name in enumerate(REASONING)}
    names = list(dict.fromkeys(levels))
    return sorted(names, key=lambda name: (rank.get(name, len(rank)), names.index(name)))


def _mean_unpruned(rows: list[dict]) -> float:
    values = [r["unpruned"] for r in rows if r.get("unpruned") is not None]
    return float(np.mean(values)) if values else math.nan


def _configs(c: Cell) -> str:
    if math.isnan(c.unpruned) or c.unpruned <= c.considered + 0.05:
        return f"{c.considered:.0f}"
    return f"{c.considered:.1f} of {c.unpruned:.1f}"


def format_table(cells: list[Cell], markdown: bool = False) -> str:
    """The success table: one line per cell, rate with its 95 % interval and mean steps."""
    head = [
        "mission",
        "robots",
        "goals",
        "level",
        "options",
        "trials",
        "success % [95 % CI]",
        "mean steps (successes)",
        "mean completion",
        "team step ms",
        "configs (pruned of)",
    ]
    lines = []
    for c in cells:
        options = (
            ""
            if c.options == "{}"
            else ", ".join(f"{k}={v}" for k, v in json.loads(c.options).items())
        )
        lines.append(
            [
                c.mission,
                str(c.robots),
                str(c.goals),
                c.reasoning,
                options,
                str(c.trials),
                f"{100 * c.rate:.1f} [{100 * c.low:.1f}, {100 * c.high:.1f}]",
                "-" if math.isnan(c.mean_steps) else f"{c.mean_steps:.1f}",
                "-" if math.isnan(c.mean_completion) else f"{c.mean_completion:.1f}",
                f"{c.decision_ms:.2f}",
                _configs(c),
            ]
        )
    if markdown:
        out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        out += ["| " + " | ".join(line) + " |" for line in lines]
        return "\n".join(out)
    widths = [max(len(h), *(len(line[i]) for line in lines)) for i, h in enumerate(head)]
    fmt = "  ".join(f"{{:<{w}}}" for w in widths)
    return "\n".join([fmt.format(*head), *(fmt.format(*line) for line in lines)])


_FONTS = {"font.size": 11, "legend.fontsize": 10, "axes.titlesize": 11}
_CAPTION_SIZE = 10


def _fitted(text: str, width_inches: float, size: float) -> str:
    """``text`` wrapped to lines that fit ``width_inches`` at font ``size`` (an average
    glyph is about 0.55 em wide), so no caption or title runs off the figure's edge."""
    return textwrap.fill(text, max(20, int(width_inches * 72 / (0.55 * size))))


def _add_caption(fig, text: str) -> float:
    """Write ``text`` under the axes, wrapped to the figure's width; return the fraction of
    the figure's height it takes, for ``tight_layout``'s rectangle."""
    fitted = _fitted(text, fig.get_figwidth() - 0.2, _CAPTION_SIZE)
    fig.text(0.01, 0.01, fitted, fontsize=_CAPTION_SIZE, ha="left", va="bottom", gid="caption")
    lines = fitted.count("\n") + 1
    return 0.02 + lines * 1.3 * _CAPTION_SIZE / 72 / fig.get_figheight()


def plot_results(
    cells: list[Cell], path, levels: Sequence[str] | None = None, fmt: str | None = None
) -> None:
    """The paper-style figure: per mission, success rate (multitask: mean completion step)
    against team size, one line per level (its own colour, marker and line style), 95 %
    bands, the legend in study order (``levels``, default :func:`study_order`).

    ``fmt`` (or else the extension of ``path``) picks the format: ``png`` (100 dpi),
    ``pdf`` or ``svg`` (vector, for a paper); the file is written at ``path`` exactly.
    """
    plt = pyplot()
    panels = sorted({(c.mission, _spec(c)) for c in cells})
    order = list(levels) if levels is not None else study_order(c.reasoning for c in cells)
    order += [lv for lv in study_order(c.reasoning for c in cells) if lv not in order]
    with plt.rc_context(_FONTS):
        fig, axes = plt.subplots(
            1, len(panels), figsize=(1.6 + 5.0 * len(panels), 4.6), squeeze=False
        )
        for ax, (mission, spec) in zip(axes[0], panels, strict=True):
            mine = [c for c in cells if (c.mission, _spec(c)) == (mission, spec)]
            present = [lv for lv in order if any(c.reasoning == lv for c in mine)]
            for k, level in enumerate(present):
                chosen = [c for c in mine if c.reasoning == level]
                # At one team size the levels' intervals would stack: set them side by side.
                shift = 0.06 * (k - (len(present) - 1) / 2) if _one_size(mine) else 0.0
                _plot_level(ax, chosen, level, mission, level_style(level), shift)
            ax.set_xlabel("robots")
            ax.set_xticks(sorted({c.robots for c in mine}))
            name = f"{spec} ({mission})" if spec else mission
            ax.set_title(
                _fitted(f"{name}, {trial_counts(mine)} per cell", 4.6, _FONTS["axes.titlesize"])
            )
            ax.grid(alpha=0.3)
        bottom = _add_caption(fig, _caption(cells))
        # One legend for every panel (a level keeps its look across missions), outside
        # the data; its entries in study order.
        shown = {h.get_label(): h for ax in axes[0] for h in ax.get_lines()}
        axes[0][-1].legend(
            [shown[lv] for lv in order if lv in shown],
            [lv for lv in order if lv in shown],
            title="level",
            loc="upper left",
            bbox_to_anchor=(1.02, 1.0),
        )
        fig.tight_layout(rect=(0, bottom, 1, 1))
        save_figure(fig, path, fmt)
    plt.close(fig)


def _spec(cell: Cell) -> str:
    """The mission file a cell's trials came from (its ``spec`` option), else ``""``."""
    try:
        return str(json.loads(cell.options).get("spec", ""))
    except (ValueError, AttributeError):
        return ""


def trial_counts(cells: Sequence[Cell]) -> str:
    """How many trials the cells hold: ``"50 trials"``, or ``"17-50 trials"`` when they
    differ.

    Examples
    --------
    >>> cell = Cell("rendezvous", 2, 2, "zero", "{}", 17, 3, 0, 1, 9, 9, 0.1, 1)
    >>> trial_counts([cell, cell._replace(trials=50)]), trial_counts([cell])
    ('17-50 trials', '17 trials')
    """
    counts = sorted({c.trials for c in cells})
    if not counts:
        return "0 trials"
    return f"{counts[0]} trials" if len(counts) == 1 else f"{counts[0]}-{counts[-1]} trials"


def _caption(cells: Sequence[Cell]) -> str:
    if cells and all(_tasks(c.mission) for c in cells):
        return (
            f"Mean completion step ({trial_counts(cells)} per cell; a failed trial counts "
            "as the step limit)."
        )
    return (
        f"Success rate over {trial_counts(cells)} per cell (the same seeds for every level); "
        "band or bar: 95 % Wilson interval."
    )


def _one_size(cells: Sequence[Cell]) -> bool:
    return len({c.robots for c in cells}) == 1


def _plot_level(
    ax, cells: list[Cell], level: str, mission: str, style: tuple, shift: float = 0.0
) -> None:
    colour, line, marker = style
    sizes = sorted({c.robots for c in cells})
    at = np.array(sizes, dtype=float) + shift
    look = {"color": colour, "linestyle": line, "marker": marker, "markersize": 7, "label": level}
    if _tasks(mission):
        means = [np.mean([c.mean_completion for c in cells if c.robots == n]) for n in sizes]
        ax.plot(at, means, **look)
        ax.set_ylabel("mean completion step (failures = limit)")
        return
    # Pool the goal counts of one team size, as the paper's per-team-size figure does.
    ok = np.array([sum(c.successes for c in cells if c.robots == n) for n in sizes])
    total = np.array([sum(c.trials for c in cells if c.robots == n) for n in sizes])
    bands = np.array([wilson_interval(k, t) for k, t in zip(ok, total, strict=True)])
    rate = 100 * ok / total
    ax.plot(at, rate, **look)
    if len(sizes) == 1:  # a band over one team size has no width: draw the interval as a bar
        spread = [rate - 100 * bands[:, 0], 100 * bands[:, 1] - rate]
        ax.errorbar(at, rate, yerr=spread, capsize=5, color=colour, linestyle="none")
    else:
        ax.fill_between(at, 100 * bands[:, 0], 100 * bands[:, 1], alpha=0.15, color=colour)
    ax.set_ylabel("success rate (%) with 95 % interval")
    ax.set_ylim(-2, 102)


def plot_levels(cells: list[Cell], path, title: str) -> None:
    """One study's levels side by side: success rate with its 95 % interval (multitask:
    mean completion step), mean steps of the successes written on each bar, the levels in
    the order given; the extension of ``path`` picks the format (PNG, PDF, SVG)."""
    plt = pyplot()
    with plt.rc_context(_FONTS):
        _level_bars(plt, cells, path, title)


def _level_bars(plt, cells: list[Cell], path, title: str) -> None:
    fig, ax = plt.subplots(figsize=(2.2 + 1.4 * len(cells), 4.8))
    names = [c.reasoning for c in cells]
    x = np.arange(len(cells))
    colours = [level_style(c.reasoning)[0] for c in cells]
    if cells and _tasks(cells[0].mission):
        values = [c.mean_completion for c in cells]
        ax.bar(x, values, color=colours, alpha=0.85)
        ax.set_ylabel("mean completion step (failures = limit)")
        caption = "Mean step at which the last task was done (a failure counts as the limit)."
    else:
        rate = np.array([100 * c.rate for c in cells])
        low = np.maximum(rate - np.array([100 * c.low for c in cells]), 0.0)
        high = np.maximum(np.array([100 * c.high for c in cells]) - rate, 0.0)
        ax.bar(x, rate, yerr=[low, high], capsize=4, color=colours, alpha=0.85)
        ax.set_ylabel("success rate (%) with 95 % interval")
        ax.set_ylim(0, 105)
        for i, c in enumerate(cells):
            if not math.isnan(c.mean_steps):
                ax.text(i, 3, f"{c.mean_steps:.0f} steps", ha="center", fontsize=10, color="white")
        caption = "Bars: success rate, 95 % Wilson interval; in a bar: mean steps of its successes."
    ax.set_xticks(x, names, rotation=20)
    ax.set_xlabel("reasoning level")
    heading = f"{title} ({trial_counts(cells)} per level, the same seeds)"
    ax.set_title(_fitted(heading, fig.get_figwidth() - 0.4, _FONTS["axes.titlesize"]))
    ax.grid(axis="y", alpha=0.3)
    bottom = _add_caption(fig, caption)
    fig.tight_layout(rect=(0, bottom, 1, 1))
    save_figure(fig, path)
    plt.close(fig)
