"""Figures fit for a paper: vector formats from run, labelled axes, a caption, honest trial
counts, panels named by mission file, one colour per level in every figure."""

from __future__ import annotations

import pytest

pytest.importorskip("matplotlib")

from epistemica.cli import main
from epistemica.sim.study import report
from epistemica.sim.study.palette import level_style
from epistemica.sim.study.report import Cell, plot_levels, plot_results

TINY = """\
mission rendezvous
robot r1..r2: random at random
goal g1..g2 at random
simulate trials 2 seed 3 steps 40 levels zero, rules_third
"""


def _cell(level: str, trials: int, robots: int = 2, options: str = "{}") -> Cell:
    return Cell("rendezvous", robots, 2, level, options, trials, trials // 2, 0.1, 0.9,
                20.0, float("nan"), 0.1, 2.0)  # fmt: skip


def test_run_writes_pdf_and_svg_beside_the_png(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "tiny.epi").write_text(TINY)
    assert main(["run", "tiny.epi", "--no-gif", "--pdf", "--svg"]) == 0
    assert "figure: runs/tiny.png, runs/tiny.pdf, runs/tiny.svg" in capsys.readouterr().out
    assert (tmp_path / "runs" / "tiny.pdf").read_bytes()[:4] == b"%PDF"
    svg = _words((tmp_path / "runs" / "tiny.svg").read_text())
    assert "reasoning level" in svg and "mean steps of its successes" in svg
    assert "2 trials per level" in svg


def _words(svg: str) -> str:
    """The SVG's text, lines joined by spaces (captions and titles wrap to fit)."""
    import re

    return " ".join(re.sub(r"<[^>]+>", " ", svg).split())


def _texts_inside(monkeypatch) -> list:
    """Record every figure saved by the report module, to look at its texts afterwards."""
    saved = []
    original = report.save_figure

    def keep(fig, path, fmt=None):
        fig.canvas.draw()
        texts = [*fig.texts, *(ax.title for ax in fig.axes)]
        saved.append([(t.get_window_extent(), fig.bbox.width) for t in texts if t.get_text()])
        original(fig, path, fmt)

    monkeypatch.setattr(report, "save_figure", keep)
    return saved


def test_titles_and_captions_stay_inside_narrow_figures(tmp_path, monkeypatch):
    saved = _texts_inside(monkeypatch)
    long = '{"spec": "a_mission_file_with_a_rather_long_name_indeed"}'
    plot_levels([_cell("rules-third", 7)], tmp_path / "one.png", "private_goal_3_long_name")
    plot_results([_cell("rules-third", 7, options=long)], tmp_path / "panel.png")
    assert len(saved) == 2
    for boxes in saved:
        for box, width in boxes:
            assert box.x0 >= 0 and box.x1 <= width + 0.5, (box, width)


@pytest.fixture(autouse=True)
def _text_as_text():
    """SVG text as text (matplotlib draws glyphs as paths by default)."""
    import matplotlib

    with matplotlib.rc_context({"svg.fonttype": "none"}):
        yield


def test_bar_colours_are_the_levels_colours(tmp_path):
    path = tmp_path / "bars.svg"
    plot_levels([_cell("zero", 4), _cell("rules-third", 4)], path, "demo")
    raw = path.read_text()
    svg = _words(raw)
    for level in ("zero", "rules-third"):
        assert level_style(level)[0] in raw
    assert "demo (4 trials per level, the same seeds)" in svg
    assert "success rate (%) with 95 % interval" in svg


def test_report_figure_counts_trials_honestly_and_names_mission_files(tmp_path):
    spec = '{"spec": "private_goal_3"}'
    cells = [_cell("zero", 17), _cell("rules-third", 50), _cell("zero", 50, 3, spec)]
    path = tmp_path / "report.svg"
    plot_results(cells, path)
    raw = path.read_text()
    svg = _words(raw)
    assert "rendezvous, 17-50 trials per cell" in svg
    assert "private_goal_3 (rendezvous), 50 trials per cell" in svg
    assert "Success rate over 17-50 trials per cell" in svg
    assert level_style("zero")[0] in raw and level_style("rules-third")[0] in raw
