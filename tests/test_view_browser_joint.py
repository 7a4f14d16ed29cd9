"""The replay page of a collaborative (joint) trial in a real headless Chromium: the map, what
each robot steers to, the tasks each robot knows of and how, and what a chosen robot knows
each teammate knows, checked against the simulated trials for every robot at every step.
The ``browser`` fixture (tests/conftest.py) skips without Chromium."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest

from epistemica.cli import main
from epistemica.mission import load_mission
from epistemica.sim import simulate

SPEC = str(Path(__file__).resolve().parents[1] / "specs/collaborative/tasks_3.epi")
LEVELS = ("rules", "rules-first")


@pytest.fixture(scope="module")
def joint(tmp_path_factory):
    """tasks_3, seed 1, third beside first (as `view` simulates them), and the two trials
    simulated here."""
    out = tmp_path_factory.mktemp("joint") / "tasks.html"
    argv = ["view", SPEC, "--trial", "1", "--level", "rules", "--compare", "rules-first"]
    assert main([*argv, "-o", str(out)]) == 0
    mission = load_mission(SPEC)
    scenario = mission.scenario(1)
    trials = [simulate(scenario, lv, seed=1, parameters=mission.parameters) for lv in LEVELS]
    return out, scenario, trials


def _target(steer: int, tasks) -> str:
    return {-1: "explore", -2: "fetch", -3: "wait"}.get(steer) or f"→{tasks[steer]}"


def _how(scenario, trial, i: int, t: int) -> tuple[int, str]:
    """When and how robot i came to know of task t, from the trial's record."""
    step = int(trial.aware_since[i, i, t])
    task = scenario.task_names[t]
    named = [e[1] for e in trial.events if e[0] == step and i in e[3] and task in map(str, e[2])]
    near = np.hypot(*(trial.trajectory[step, i, :2] - scenario.tasks[t])) <= scenario.sensing_range
    return step, named[0] if named else "seen" if near else "told"


#: Everything the tests read of one column at one step, in one round trip.
_READ = """(k => {
  const q = (s) => [...document.querySelectorAll(`#trial-${k} ${s}`)];
  return {
    robots: q("circle.robot").map(c => [c.dataset.robot, +c.getAttribute("cx"),
                                        +c.getAttribute("cy")]),
    stars: q("polygon.goal").map(g => g.getAttribute("points").split(" ")[0].split(",")
                                      .map(Number)),
    done: q("polygon.goal.done").map(g => g.dataset.name),
    names: q("text.goal-name").map(t => t.textContent),
    onMap: q("text.target").map(t => [t.dataset.robot, t.textContent]),
    targets: q("#targets-" + k + " td.target").map(t => t.textContent),
    known: q("#knowledge-" + k + " td.goal-cell").map(t => t.textContent),
    model: q("#model-" + k + " td.goal-cell").map(t => t.textContent),
    modelRows: q("#model-" + k + " tr[data-robot]").map(r => r.dataset.robot),
  };
})"""


def test_every_robot_and_task_at_every_step_is_the_trials(browser, joint):
    page, s, trials = joint
    browser.open(page, "window.epistemicaView")
    names, tasks, n = list(s.robot_names), list(s.task_names), s.n_robots
    verdicts = "; ".join(
        f"{lv} succeeded at step {t.steps}" if t.success else f"{lv} failed within {t.steps} steps"
        for lv, t in zip(LEVELS, trials, strict=True)
    )
    assert browser.js("document.title") == f"tasks_3: 3 robots, seed 1: {verdicts}"
    assert browser.js("window.epistemicaView.last") == max(t.steps for t in trials)
    # the robot whose model of its teammates is shown: the one that fetched most (third)
    fetches = [(t.steer_to == -2).sum(axis=0) for t in trials]
    focus = [int(np.argmax(f)) for f in fetches]
    assert fetches[0].max() > 0 and fetches[1].max() == 0 and focus[1] == 0
    for step in range(max(t.steps for t in trials) + 1):
        browser.js(f"window.epistemicaView.setStep({step})")
        for k, trial in enumerate(trials):
            got = browser.js(f"{_READ}({k})")
            at, decided = min(step, trial.steps), min(step, trial.steps - 1)
            # the map: every robot where the trial has it (metres to pixels by two tasks)
            (x0, y0), (x1, _) = got["stars"][0], got["stars"][1]
            scale = (x1 - x0) / (s.tasks[1, 0] - s.tasks[0, 0])
            y0 += 10  # a star's first point is 10 px above its centre
            pose = trial.trajectory[at]
            assert [r[0] for r in got["robots"]] == names  # none stacked on these seeds
            for (_, cx, cy), (x, y, _) in zip(got["robots"], pose, strict=True):
                assert cx == pytest.approx(x0 + (x - s.tasks[0, 0]) * scale, abs=0.6)
                assert cy == pytest.approx(y0 - (y - s.tasks[0, 1]) * scale, abs=0.6)
            # tasks: the robots each needs, done (hollow, with its step) from its step on
            done = [t for t in range(len(tasks)) if 0 <= trial.tasks_done[t] <= at]
            assert got["done"] == [tasks[t] for t in done]
            assert got["names"] == [
                f"{name} ×{need}" + (f" (done at {trial.tasks_done[t]})" if t in done else "")
                for t, (name, need) in enumerate(zip(tasks, s.needs, strict=True))
            ]
            # what each robot steers to, beside it and in the table
            steer = [_target(int(v), tasks) for v in trial.steer_to[decided]]
            assert got["onMap"] == [[r, v] for r, v in zip(names, steer, strict=True)]
            assert got["targets"] == steer
            # the tasks each robot knows of
            knows = trial.knows[decided]
            assert [c[0] for c in got["known"]] == [
                "✓" if knows[i, t] else "·" for i in range(n) for t in range(len(tasks))
            ]
            # what the focus robot knows each teammate knows of, since when
            f, since = focus[k], trial.aware_since
            assert got["modelRows"] == [names[j] for j in range(n) if j != f]
            assert got["model"] == [
                f"✓ {since[f, j, t]}" if 0 <= since[f, j, t] <= at else "·"
                for j in range(n)
                if j != f
                for t in range(len(tasks))
            ]


def test_how_each_robot_learned_each_task_and_another_robots_model(browser, joint):
    page, s, trials = joint
    browser.open(page, "window.epistemicaView")
    browser.js(f"window.epistemicaView.setStep({trials[0].steps})")
    cells = browser.texts("#knowledge-0 td.goal-cell")
    n, m = s.n_robots, s.n_tasks
    expected = []
    for i in range(n):
        for t in range(m):
            known = trials[0].knows[-1, i, t]
            expected.append("✓ {1} {0}".format(*_how(s, trials[0], i, t)) if known else "·")
    assert cells == expected and "✓ heading" in " ".join(cells)  # one learned by an event
    # r3 chosen: its rows, what it knows r1 and r2 know of
    browser.js(
        "(s => { s.value = '2'; s.dispatchEvent(new Event('change')); })"
        "(document.querySelector('#model-robot-0'))"
    )
    assert browser.texts("#model-0 tr[data-robot] th") == ["r1", "r2"]
    since, at = trials[0].aware_since, trials[0].steps
    assert browser.texts("#model-0 td.goal-cell") == [
        f"✓ {since[2, j, t]}" if 0 <= since[2, j, t] <= at else "·"
        for j in (0, 1)
        for t in range(m)
    ]


def test_a_results_file_of_collaborative_trials_views(browser, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    text = Path(SPEC).read_text().replace("steps 400", "steps 60")
    (tmp_path / "small.epi").write_text(text)
    assert main(["run", "small.epi", "--trials", "1", "--levels", "rules", "--no-gif"]) == 0
    assert main(["view", "runs/small.sqlite", "-o", "page.html"]) == 0
    browser.open(tmp_path / "page.html", "window.epistemicaView")
    m = load_mission(str(tmp_path / "small.epi"))
    trial = simulate(m.scenario(0), "rules", seed=0, parameters=m.parameters)
    browser.js("window.epistemicaView.setStep(5)")
    assert browser.texts("#targets-0 td.target") == [
        _target(int(v), m.scenario(0).task_names) for v in trial.steer_to[5]
    ]


def test_each_robots_targets_over_the_trial_are_its_record(browser, joint):
    page, s, trials = joint
    browser.open(page, "window.epistemicaView")
    for k, trial in enumerate(trials):
        bars = browser.js(
            f"[...document.querySelectorAll('#timeline-{k} rect.segment')].map(r => "
            "[r.dataset.robot, r.dataset.target, +r.dataset.from, +r.dataset.to])"
        )
        for i, name in enumerate(s.robot_names):
            mine = [bar[1:] for bar in bars if bar[0] == name]
            drawn = [what for what, a, b in mine for _ in range(a, b + 1)]
            assert drawn == [_target(int(v), s.task_names) for v in trial.steer_to[:, i]]
            # one bar per run: neighbours differ
            assert all(x[0] != y[0] for x, y in pairwise(mine))
