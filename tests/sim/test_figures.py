"""`epistemica simulate` and the trial pictures: exit codes, JSON, PNG and GIF read back."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from importlib import import_module
from pathlib import Path

import numpy as np
import pytest

from epistemica.aif.teammates import TYPE_PRIOR
from epistemica.cli import main
from epistemica.del_.errors import EpistemicaError
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.figures import TraceFrame, animate_trial, focus_robot, plot_trial
from epistemica.sim.study.palette import ROBOT_COLOURS
from epistemica.sim.study.report import plot_results, study_order, summarise
from epistemica.sim.study.trace import trial_trace

PIL = pytest.importorskip("PIL.Image")
SPECS = Path(__file__).resolve().parents[2] / "specs"


def test_success_and_failure_exit_codes_and_json(capsys):
    # Seed 2, allocation of 4 robots: third order succeeds; greedy rendezvous of 3 fails.
    assert main(["simulate", "--mission", "allocation", "--robots", "4", "--seed", "2"]) == 0
    assert "succeeded" in capsys.readouterr().out
    status = main(
        [
            "simulate",
            "--robots",
            "3",
            "--seed",
            "0",
            "--reasoning",
            "zero",
            "--json",
            "--max-steps",
            "20",
        ]
    )
    record = json.loads(capsys.readouterr().out)
    trial = simulate(Scenario.paper("rendezvous", 3, seed=0, max_steps=20), "zero", seed=0)
    assert status == (0 if trial.success else 1)
    assert record["success"] == trial.success and record["steps"] == trial.steps
    assert record["sensors"] == list(trial_scenario_sensors(0))


def trial_scenario_sensors(seed):
    return Scenario.paper("rendezvous", 3, seed=seed).sensors


def test_bad_input_exits_2_without_traceback(capsys):
    # In this process (main, what the script calls); the script's own exit status:
    # tests/test_cli_check.py::test_python_dash_m_runs_the_main_job.
    for argv in (["--robots", "0"], ["--reasoning", "telepathy"], ["--mission", "juggle"]):
        status = main(["simulate", *argv])
        err = capsys.readouterr().err
        assert status == 2 and "Traceback" not in err
        assert "hint:" in err


def test_png_has_the_map(tmp_path):
    s = Scenario.paper("allocation", 3, seed=1)
    path = tmp_path / "t.png"
    plot_trial(s, simulate(s, "convention", seed=1), path)
    image = np.asarray(PIL.open(path).convert("RGB"), dtype=float)
    assert image.shape[:2] == (640, 640)
    assert image.std() > 10  # not a blank canvas


def test_gif_frames_follow_the_trial(tmp_path):
    s = Scenario.paper("rendezvous", 2, 2, seed=3).replace(max_steps=12)
    trial = simulate(s, "rules-third", seed=3)
    path = tmp_path / "t.gif"
    frames = animate_trial(s, trial, path)
    assert frames == min(trial.steps + 1, 60)
    with PIL.open(path) as gif:
        assert gif.n_frames == frames
        first, last = np.asarray(gif.convert("RGB")), None
        gif.seek(gif.n_frames - 1)
        last = np.asarray(gif.convert("RGB"))
    assert not np.array_equal(first, last)  # the robots moved


def test_cli_writes_both_pictures(tmp_path):
    png, gif = tmp_path / "a.png", tmp_path / "a.gif"
    main(["simulate", "--robots", "2", "--max-steps", "5", "--png", str(png), "--gif", str(gif)])
    assert png.stat().st_size > 10_000 and gif.stat().st_size > 10_000


def test_missing_matplotlib_names_the_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    s = Scenario.paper("rendezvous", 2, 2, seed=0).replace(max_steps=3)
    with pytest.raises(EpistemicaError, match="matplotlib") as err:
        plot_trial(s, simulate(s, "zero", seed=0), tmp_path / "x.png")
    assert "epistemica[plot]" in err.value.hint


# --- the animation's content, read from its artists ----------------------------------


def _texts(fig):
    from matplotlib.text import Text

    return [t for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]


@pytest.fixture(scope="module")
def relocated():
    """The false-belief mission: an event at step 0 seen by some robots, nested sets that
    differ from the teammates' own."""
    from epistemica.mission import load_mission

    mission = load_mission(str(SPECS / "nested" / "relocated_3.epi"))
    s = mission.scenario(0)
    t = simulate(
        s, "rules-third", seed=0, policies=mission.policies(0), parameters=mission.parameters
    )
    return s, t, trial_trace(s, t)


def test_animation_frame_shows_names_sensing_estimates_and_sets(relocated):
    s, trial, trace = relocated
    frame = TraceFrame(trace, s.mission)
    try:
        frame.draw(3)
        gids = [a.get_gid() for a in frame.fig.findobj() if a.get_gid()]
        robots, goals = list(s.robot_names), list(s.goal_names)
        assert robots == ["r1", "r2", "r3"] and goals == ["g1", "g2", "g3", "g4", "g5"]
        assert sorted(g for g in gids if g.startswith("sensing:")) == [
            f"sensing:{r}" for r in robots
        ]
        assert [g for g in gids if g.startswith("goal:")] == [f"goal:{g}" for g in goals]
        assert [g for g in gids if g.startswith("robot:")] == [f"robot:{r}" for r in robots]
        # The sensing circles follow the robots, with the trial's radius.
        for circle, pose in zip(frame.sensing, trial.trajectory[3], strict=True):
            assert np.allclose(circle.center, pose[:2], atol=0.01)
            assert circle.radius == s.sensing_range
        # r1's estimate of r2 is drawn where the trial recorded it.
        mark = next(a for a in frame.fig.findobj() if a.get_gid() == "estimate:r1->r2")
        assert np.allclose(np.asarray(mark.get_data())[:, 0], trial.estimates[3, 0, 1], atol=0.06)
        # Goals are black, robots take the palette: a colour never means both.
        star = next(a for a in frame.fig.findobj() if a.get_gid() == "goal:g1")
        assert star.get_color() == "k"
        assert all(c not in ("k", "0.8", "#7f7f7f") for c in ROBOT_COLOURS)
        belief = frame.belief_axes
        assert [t.get_text() for t in belief.get_xticklabels()] == goals
        assert [t.get_text() for t in belief.get_yticklabels()] == robots
        assert np.allclose(frame.belief_image.get_array(), trial.goal_belief[3], atol=6e-4)
        # Own sets solid, and the focus robot's model of each teammate's set dashed.
        f = focus_robot(trace)
        lines = {line.get_label(): line for line in frame.sets_axes.get_lines()}
        for j, name in enumerate(robots):
            assert np.array_equal(lines[name].get_ydata(), trial.considered[:, j])
            if j != f:
                nested = lines[f"{robots[f]}'s model of {name}'s"]
                assert nested.get_linestyle() == "--"
                assert np.array_equal(nested.get_ydata(), trial.modelled[:, f, j])
        assert (trial.modelled[:, f] != trial.considered).any()  # the focus differs somewhere
        assert min(t.get_fontsize() for t in _texts(frame.fig)) >= 10
        # Every legend (markers included) lies inside the picture.
        frame.fig.canvas.draw()
        page = frame.fig.bbox
        for ax in (frame.map_axes, frame.sets_axes):
            box = ax.get_legend().get_window_extent()
            assert page.x0 <= box.x0 and box.x1 <= page.x1 and page.y0 <= box.y0, ax
    finally:
        frame.close()


def test_a_settle_event_names_the_robot_and_the_goal_it_settled_at():
    from epistemica.mission import load_mission

    mission = load_mission(str(SPECS / "stress" / "rendezvous_radius_3.epi"))
    s = mission.scenario(0)
    trace = trial_trace(s, simulate(s, "rules-third", seed=0, policies=mission.policies(0)))
    settles = [e for e in trace["events"] if e[1] == "settle"]
    assert settles
    for step, _, (robot, goal), _observers in settles:
        i, g = trace["robots"].index(robot), trace["goals"].index(goal)
        gap = np.subtract(trace["poses"][step][i][:2], trace["goal_positions"][g])
        assert np.hypot(*gap) <= trace["success_radius"] + 0.01


def test_the_teammate_types_a_robot_reads_are_recorded_and_drawn():
    from epistemica.mission import load_mission

    mission = load_mission(str(SPECS / "stress" / "rendezvous_adhoc_stationary_silent_3.epi"))
    s = mission.scenario(0)
    trial = simulate(s, "rules-third", seed=0, policies=mission.policies(0))
    trace = trial_trace(s, trial)
    plain = trial_trace(s, simulate(s, "convention", seed=0, policies=mission.policies(0)))
    assert "teammate_types" not in plain  # no level kept models: nothing recorded
    types = np.asarray(trace["teammate_types"], dtype=float)  # (T, n, n, K)
    assert types.shape == (trial.steps, 3, 3, len(trace["types"]))
    kept = [i for i, level in enumerate(trial.policies) if level == "rules-third"]
    assert np.allclose(types[:, kept].sum(axis=-1), 1.0, atol=0.03)  # posteriors, rounded
    assert np.isnan(types[:, [i for i in range(3) if i not in kept]]).all()
    frame = TraceFrame(trace)
    try:
        step = trial.steps - 1
        frame.draw(step, step - 1)
        reader = frame.focus if frame.focus in kept else kept[0]
        text = frame.reading.get_text().splitlines()
        name = trace["robots"][reader]
        assert text[:2] == [f"{name} reads each", "teammate as (likeliest"]
        assert text[3] == f"prior: team {TYPE_PRIOR[0]:.2f}):"  # the library's first type
        others = [j for j in range(3) if j != reader]
        shown = []
        for line, j in zip(text[4:], others, strict=False):
            k = int(np.argmax(types[step, reader, j]))
            assert (
                line == f"{trace['robots'][j]} {trace['types'][k]} {types[step, reader, j, k]:.2f}"
            )
            shown.append(trace["types"][k])
        # then what each behaviour shown means, once each
        key = " ".join(text[4 + len(others) :])
        for name in dict.fromkeys(shown):
            assert f"{name}:" in key
    finally:
        frame.close()


def test_a_version_1_trace_is_still_read_and_drawn(relocated):
    from epistemica.sim.study.trace import decode, encode

    _s, _trial, trace = relocated
    old = {**trace, "version": 1, "events": [[9, "settle", [1, 0], [0, 1]]]}
    old = decode(encode(old))
    frame = TraceFrame(old)
    try:
        frame.draw(9, 8)
        names = old["robots"][0] + ", " + old["robots"][1]
        assert f"step 9: settle, seen by {names}" in frame.event_lines.get_text()
    finally:
        frame.close()


def test_events_are_listed_and_ringed_when_they_happen(relocated):
    s, _trial, trace = relocated
    (step, name, arguments, observers), *_ = trace["events"]
    frame = TraceFrame(trace)
    try:
        frame.draw(step, step - 1)
        rings = [a for a in frame.fig.findobj() if a.get_gid() == f"event:{name}"]
        assert len(rings) == len(observers) >= 1
        seen = ", ".join(s.robot_names[o] for o in observers)
        about = f"({', '.join(arguments)})" if arguments else ""
        assert f"step {step}: {name}{about}, seen by {seen}" in frame.event_lines.get_text()
        frame.draw(step + 2, step + 1)
        assert not [a for a in frame.fig.findobj() if a.get_gid() == f"event:{name}"]
    finally:
        frame.close()


def test_no_sensing_circles_with_unlimited_sensing():
    s = Scenario.paper("rendezvous", 2, 2, seed=0, max_steps=4)
    frame = TraceFrame(trial_trace(s, simulate(s, "rules-third", seed=0)))
    try:
        assert s.sensing_range is None and frame.sensing == []
    finally:
        frame.close()


# --- the report figure ---------------------------------------------------------------


def _cells(levels):
    rows = [
        {"mission": "rendezvous", "robots": n, "goals": n, "reasoning": level, "options": "{}",
         "success": (seed + k) % 3 != 0, "steps": 20, "completion_step": None,
         "decision_ms": 0.1, "considered": 1.0}
        for k, level in enumerate(levels) for n in (2, 3) for seed in range(6)
    ]  # fmt: skip
    return summarise(rows)


def test_report_figure_in_study_order_with_markers_and_styles(tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    saved = []
    monkeypatch.setattr(Figure, "savefig", lambda self, *a, **k: saved.append(self))
    levels = ["rules-third", "zero", "rules-first", "rules-third-shared", "convention"]
    plot_results(_cells(levels), tmp_path / "r.png")
    (ax,) = saved[0].axes
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert (
        legend
        == study_order(levels)
        == ["zero", "convention", "rules-first", "rules-third", "rules-third-shared"]
    )
    lines = [line for line in ax.get_lines() if line.get_label() in legend]
    looks = {(line.get_marker(), line.get_linestyle(), line.get_color()) for line in lines}
    assert len(looks) == len(levels) and len({lk[0] for lk in looks}) == len(levels)
    assert min(t.get_fontsize() for t in _texts(saved[0])) >= 10


def test_report_writes_png_pdf_and_svg(tmp_path, capsys):
    from epistemica.sim.study.store import ResultStore

    db = tmp_path / "r.sqlite"
    with ResultStore(db) as store:
        for i, c in enumerate(_cells(["zero", "rules-third"])):
            store.add({"id": str(i), "mission": c.mission, "robots": c.robots, "goals": c.goals,
                       "reasoning": c.reasoning, "seed": i, "options": "{}", "success": 1,
                       "steps": 9, "completion_step": None, "wall_time": 0.1,
                       "decision_ms": 0.1, "considered": 1.0, "version": "0"})  # fmt: skip
    out = {ext: tmp_path / f"fig.{ext}" for ext in ("png", "pdf", "svg")}
    argv = ["report", str(db), "--png", str(out["png"]), "--pdf", str(out["pdf"])]
    assert main([*argv, "--svg", str(out["svg"])]) == 0
    assert out["png"].read_bytes().startswith(b"\x89PNG")
    assert out["pdf"].read_bytes().startswith(b"%PDF")
    assert b"<svg" in out["svg"].read_bytes()[:2000]
    assert "--pdf" in _help(["report", "--help"]) and "95 %%" not in _help(["report", "--help"])
    # The format is the option's, at exactly the path given, extension or not.
    again = ["report", str(db), "--png", str(tmp_path / "plain"), "--svg", str(out["png"])]
    assert main([*again, "--force"]) == 0  # fig.png exists: replaced only with --force
    assert (tmp_path / "plain").read_bytes().startswith(b"\x89PNG")
    assert b"<svg" in out["png"].read_bytes()[:2000]
    assert not (tmp_path / "plain.png").exists()


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_a_figure_that_cannot_be_written_is_an_error_not_a_success(tmp_path, capsys, few_frames):
    from epistemica.sim.study.store import ResultStore

    db = tmp_path / "r.sqlite"
    with ResultStore(db) as store:
        store.add({"id": "0", "mission": "rendezvous", "robots": 2, "goals": 2,
                   "reasoning": "rules-third", "seed": 0, "options": "{}", "success": 1,
                   "steps": 9, "completion_step": None, "wall_time": 0.1,
                   "decision_ms": 0.1, "considered": 1.0, "version": "0"})  # fmt: skip
    assert main(["report", str(db), "--png", "/dev/full"]) == 2
    err = capsys.readouterr().err
    assert "cannot write the figure /dev/full" in err and "Traceback" not in err
    assert main(["report", str(db), "--pdf", str(tmp_path / "missing" / "f.pdf")]) == 2
    assert main(["simulate", "--mission", "rendezvous", "--robots", "2", "--gif", "/dev/full"]) == 2
    assert "cannot write the animation /dev/full" in capsys.readouterr().err


def _help(argv) -> str:
    proc = subprocess.run(
        [sys.executable, "-m", "epistemica", *argv], capture_output=True, text=True, check=True
    )
    return proc.stdout


def test_run_animates_the_first_trial_where_the_levels_disagree(
    tmp_path, capsys, monkeypatch, few_frames
):
    from epistemica.mission import load_mission

    spec = str(SPECS / "rendezvous.epi")
    argv = ["run", spec, "--trials", "4", "--levels", "zero,rules-third", "--workers", "1"]
    animated = []
    with monkeypatch.context() as m:  # the trial chosen is checked here, its GIF below
        m.setattr(import_module("epistemica.cli.run"), "_animate", lambda _, *a: animated.append(a))
        assert main([*argv, "--out", str(tmp_path / "r.sqlite")]) == 0
    printed = capsys.readouterr().out
    mission = load_mission(spec)
    outcomes = {
        seed: {
            level: simulate(mission.scenario(seed), level, seed=seed,
                            policies=mission.policies(seed), parameters=mission.parameters).success
            for level in ("zero", "rules-third")
        }
        for seed in range(4)
    }  # fmt: skip
    # rules-third succeeding where zero fails comes first; any disagreement next.
    decided = [seed for seed, o in outcomes.items() if o["rules-third"] and not o["zero"]]
    disputed = decided or [seed for seed, o in outcomes.items() if len(set(o.values())) > 1]
    expected = f"seed {disputed[0]}: the first where" if disputed else "the levels agree"
    assert f"animation (rules-third, {expected}" in printed
    assert [a[:2] for a in animated] == [("rules-third", disputed[0] if disputed else 0)]
    assert main([*argv, "--out", str(tmp_path / "s.sqlite"), "--trial", "2"]) == 0
    assert "animation (rules-third, seed 2)" in capsys.readouterr().out
    with PIL.open(tmp_path / "s.gif") as gif:
        assert gif.n_frames >= 2
