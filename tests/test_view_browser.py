"""The HTML pages in a real headless Chromium: drawn content, play/pause/scrub, formula box.

Chromium is driven over the DevTools protocol on a pipe (tests/_browser.py). Without a
Chromium executable (Debian's ``chromium`` package) the module is skipped, with the reason.
"""

from __future__ import annotations

import json
import os
import random
import time

import numpy as np
import pytest
from _browser import CHROMIUM

from epistemica.aif.teammates import TYPE_PRIOR
from epistemica.cli import main
from epistemica.del_ import evaluate, load_spec
from epistemica.mission import parse_mission
from epistemica.model_json import world_names
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.palette import ROBOT_COLOURS, TYPE_MEANINGS, focus_robot
from epistemica.sim.study.trace import trial_trace

pytestmark = pytest.mark.skipif(
    CHROMIUM is None, reason="no Chromium executable on PATH (Debian: apt-get install chromium)"
)
PIL = pytest.importorskip("PIL.Image")
SPECS = os.path.join(os.path.dirname(__file__), "..", "specs", "puzzles")


@pytest.fixture(scope="module")
def trial_page(tmp_path_factory):
    """A 5-robot trial with a sensing range, its trace and its page."""
    s = Scenario.paper("rendezvous", 5, seed=2, max_steps=30, sensing_range=8.0)
    trace = trial_trace(s, simulate(s, "rules-third", seed=2))
    path = tmp_path_factory.mktemp("view") / "trace.json"
    path.write_text(json.dumps(trace))
    out = path.with_suffix(".html")
    assert main(["view", str(path), "-o", str(out)]) == 0
    return trace, out


def _colour_pixels(image: np.ndarray, colour: str) -> int:
    rgb = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(image - rgb).sum(axis=2) < 30).sum())


def test_trial_page_draws_every_robot_and_goal(browser, trial_page):
    trace, page = trial_page
    browser.open(page, "window.epistemicaView")
    names = browser.js("[...document.querySelectorAll('circle.robot')].map(c => c.dataset.robot)")
    assert names == trace["robots"] == ["r1", "r2", "r3", "r4", "r5"]
    assert browser.js("document.querySelectorAll('circle.sensing').length") == 5
    goals = browser.js("[...document.querySelectorAll('polygon.goal')].map(g => g.dataset.name)")
    assert goals == trace["goals"]
    header = browser.js("[...document.querySelectorAll('#belief-0 th')].map(t => t.textContent)")
    assert header[1:6] == trace["goals"] and header[6:] == trace["robots"]
    # The map on the screen: not blank, and every robot's colour is drawn there.
    box = browser.js("(() => { const r = document.querySelector('#map-0').getBoundingClientRect(); "
                     "return [r.left, r.top, r.right, r.bottom].map(Math.round); })()")  # fmt: skip
    shot = browser.screenshot()
    region = shot[box[1] : box[3], box[0] : box[2]]
    assert (np.abs(region - 252).sum(axis=2) > 60).mean() > 0.02
    for colour in ROBOT_COLOURS[:5]:
        assert _colour_pixels(region, colour) > 20, colour
    outside = shot[box[3] + 200 :, : box[0] + 1]
    assert _colour_pixels(outside, ROBOT_COLOURS[0]) < _colour_pixels(region, ROBOT_COLOURS[0])


def test_play_pause_and_scrub(browser, trial_page):
    trace, page = trial_page
    browser.open(page, "window.epistemicaView")
    first = browser.js("document.querySelector('circle.robot').getAttribute('cx')")
    browser.click("#play")
    browser.wait("window.epistemicaView.step >= 3")
    assert browser.js("document.querySelector('#play').textContent") == "Pause"
    browser.click("#play")
    paused = browser.js("window.epistemicaView.step")
    time.sleep(0.5)
    assert browser.js("window.epistemicaView.step") == paused
    assert browser.js("document.querySelector('circle.robot').getAttribute('cx')") != first
    # A click near the right end of the slider jumps there; the panels follow the trace.
    browser.click("#step", 0.97)
    step = browser.js("window.epistemicaView.step")
    assert step >= 0.85 * trace["steps"]
    cells = browser.js("[...document.querySelectorAll('#belief-0 td')].map(t => t.textContent)")
    decided = min(step, trace["steps"] - 1)
    expected = [f"{v:.2f}" for row in trace["goal_belief"][decided] for v in row]
    assert cells == expected
    assert f"step {step} of {trace['steps']}" in browser.js("document.body.innerText")
    # What a robot reads of its teammates (teammate models): the trace's most likely type.
    types = trace["teammate_types"]
    kept = [i for i in range(5) if any(None not in row for st in types for row in st[i])]
    reader = focus_robot(trace) if focus_robot(trace) in kept else kept[0]
    assert _texts(browser, "#reading-0 tr:first-child th")[1:] == trace["types"]
    rows = [j for j in range(5) if j != reader]
    assert _texts(browser, "#reading-0 tr[data-robot] th") == [trace["robots"][j] for j in rows]
    cells = _texts(browser, "#reading-0 td.goal-cell")
    table = [trace["teammate_types"][decided][reader][j] for j in rows]
    assert cells == [f"{v:.2f}" if v is not None else "n/c" for row in table for v in row]
    likeliest = _texts(browser, "#reading-0 td.likeliest")
    assert likeliest == [f"{max(row):.2f}" for row in table if None not in row] and likeliest
    key = browser.js("document.querySelector('#reading-key-0').textContent")
    for name, meaning in TYPE_MEANINGS.items():
        assert f"{name}: {meaning}" in key
    assert f"{trace['types'][0]} {TYPE_PRIOR[0]:.2f}" in key  # the prior, before any move


def _random_formula(rng: random.Random, agents: list[str], atoms: list[str], depth: int) -> str:
    if depth == 0 or rng.random() < 0.25:
        return rng.choice(atoms)
    pick = rng.randrange(9)
    a, b = rng.choice(agents), _random_formula(rng, agents, atoms, depth - 1)
    group = ", ".join(rng.sample(agents, rng.randint(1, len(agents))))
    if pick < 3:
        c = _random_formula(rng, agents, atoms, depth - 1)
        return f"({b} {['&', '|', '->'][pick]} {c})"
    return [f"~{b}", f"K[{a}] {b}", f"B[{a}] {b}", f"Kw[{a}] {b}", f"C[{group}] {b}",
            f"D[{group}] {b}"][pick - 3]  # fmt: skip


@pytest.mark.parametrize(
    ("spec", "after"), [("muddy_children.epi", "father"), ("sally_anne.epi", "sally_leaves")]
)
def test_formula_box_agrees_with_the_checker(browser, tmp_path, spec, after):
    path = os.path.join(SPECS, spec)
    page = tmp_path / "model.html"
    assert main(["show", path, "--after", after, "--html", str(page)]) == 0
    browser.open(page, "window.epistemicaModel")
    model = load_spec(path).model
    for action in [after]:
        model = model.update(load_spec(path).actions[action])
    names = world_names(model)
    ordered = [names[w] for w in model.worlds]
    rng = random.Random(7)
    atoms = sorted(model.atoms)
    formulas = [_random_formula(rng, list(model.agents), atoms, 3) for _ in range(40)]
    in_page = browser.js(
        f"{json.dumps(formulas)}.map(f => window.epistemicaModel.evaluate(f).worlds)"
    )
    for formula, worlds in zip(formulas, in_page, strict=True):
        truth = evaluate(model, formula)
        assert worlds == [n for n, t in zip(ordered, truth.tolist(), strict=True) if t], formula
    # Typed into the box and clicked: the verdict at the designated worlds and the table.
    formula = formulas[0]
    browser.js("document.querySelector('#formula').value = ''")
    browser.click("#formula")
    browser.send("Input.insertText", text=formula)
    browser.click("#evaluate")
    verdict = bool(evaluate(model, formula)[model.designated_positions].all())
    result = browser.js("document.querySelector('#result').textContent")
    assert result.startswith("holds" if verdict else "does not hold"), result
    marks = browser.js("[...document.querySelectorAll('td.mark')].map(t => t.textContent)")
    assert marks == [str(t).lower() for t in evaluate(model, formula).tolist()]
    browser.js("(b => { b.focus(); b.setSelectionRange(b.value.length, b.value.length); })"
               "(document.querySelector('#formula'))")  # fmt: skip
    browser.send("Input.insertText", text=" & nosuchatom")
    browser.click("#evaluate")
    assert "unknown atom 'nosuchatom'" in browser.js(
        "document.querySelector('#result').textContent"
    )


PRIVATE = os.path.join(os.path.dirname(__file__), "..", "specs", "nested", "private_goal_3.epi")


@pytest.fixture(scope="module")
def compared(tmp_path_factory):
    """private_goal_3, seed 4, rules-third beside rules-first; the two trials simulated here too."""
    out = tmp_path_factory.mktemp("compare") / "private.html"
    argv = ["view", PRIVATE, "--trial", "4", "--level", "rules-third", "--compare", "rules-first"]
    assert main([*argv, "-o", str(out)]) == 0
    with open(PRIVATE) as f:
        mission = parse_mission(f.read(), PRIVATE)
    scenario = mission.scenario(4)
    trials = [
        simulate(
            scenario, level, seed=4, policies=mission.policies(4), parameters=mission.parameters
        )
        for level in ("rules-third", "rules-first")
    ]
    return out, [trial_trace(scenario, t) for t in trials], trials


def _texts(browser, selector: str) -> list[str]:
    return browser.js(f"[...document.querySelectorAll({json.dumps(selector)})]"
                      ".map(e => e.textContent)")  # fmt: skip


def test_both_levels_are_drawn_with_one_slider_and_a_title_saying_how_each_did(browser, compared):
    page, _, trials = compared
    browser.open(page, "window.epistemicaView")
    verdicts = [
        f"succeeded at step {t.steps}" if t.success else f"failed within {t.steps} steps"
        for t in trials
    ]
    assert browser.js("document.title") == (
        f"private_goal_3: 3 robots, seed 4: rules-third {verdicts[0]}; rules-first {verdicts[1]}"
    )
    assert trials[0].success and not trials[1].success  # the levels disagree on this seed
    assert browser.js("[...document.querySelectorAll('.column')].map(c => c.dataset.level)") == [
        "rules-third",
        "rules-first",
    ]
    assert browser.js("window.epistemicaView.last") == max(t.steps for t in trials)
    # One slider moves both maps; a column whose trial ended keeps its last poses.
    cx = "[...document.querySelectorAll('#map-{} circle.robot')].map(c => +c.getAttribute('cx'))"
    browser.js(f"window.epistemicaView.setStep({trials[0].steps})")
    done, before = browser.js(cx.format(0)), browser.js(cx.format(1))
    browser.js(f"window.epistemicaView.setStep({trials[1].steps})")
    assert browser.js(cx.format(0)) == done
    moved = np.abs(trials[1].trajectory[-1] - trials[1].trajectory[trials[0].steps]).max()
    assert (browser.js(cx.format(1)) != before) == (moved > 0.05)


def test_the_knowledge_panels_show_who_knows_what_at_every_step(browser, compared):
    page, traces, trials = compared
    browser.open(page, "window.epistemicaView")
    goals = traces[0]["goals"]
    focus = focus_robot(traces[0])
    assert traces[0]["robots"][focus] == "r1"  # the robot that alone knows of g4
    wrong_somewhere = [False, False]
    for step in range(max(t.steps for t in trials) + 1):
        browser.js(f"window.epistemicaView.setStep({step})")
        for k, (trace, trial) in enumerate(zip(traces, trials, strict=True)):
            t = min(step, trial.steps - 1)
            known = trial.known_goals[t]
            cells = _texts(browser, f"#knowledge-{k} td.goal-cell")
            assert [c[0] for c in cells] == [
                "✓" if known[i, i, g] else "·" for i in range(3) for g in range(len(goals))
            ]
            model = _texts(browser, f"#model-{k} td.goal-cell")
            assert model == [
                "✓" if known[focus, j, g] else "✗"
                for j in range(3)
                if j != focus
                for g in range(len(goals))
            ]
            beliefs = _texts(browser, f"#belief-{k} td")
            assert beliefs == [
                f"{v:.2f}" if trial.goal_belief[t, i].sum() > 0 else "n/c"
                for i in range(3)
                for v in trace["goal_belief"][t][i]  # as stored: rounded to 3 decimals
            ]
            # Expectations a robot's own knowledge contradicts, computed from the trial.
            focal = trial.focal[t]
            contradicted = [
                f"{trace['robots'][j]}→{goals[focal[i, j]]}"
                for i in range(3)
                if focal[i, i] >= 0
                for j in range(3)
                if j != i and focal[i, j] >= 0 and not known[i, j, focal[i, j]]
            ]
            assert _texts(browser, f"#knowledge-{k} span.expect.wrong") == contradicted
            wrong_somewhere[k] |= bool(contradicted)
    # first expects its teammates at g4, which it knows they do not know of; third never.
    assert wrong_somewhere == [False, True]
    learned = [c for c in traces[1]["knows"] if c[0] > 0 and c[1] == c[2] and c[4]]
    for step, i, _, g, _, how in learned:
        browser.js(f"window.epistemicaView.setStep({step})")
        cell = _texts(browser, f"#knowledge-1 tr[data-robot=r{i + 1}] td.goal-cell")[g]
        assert cell == f"✓ {how} {step}"


def test_obstacles_closed_goals_axes_and_a_robot_under_another_are_drawn(browser, tmp_path):
    square = [[10.0, 4.0], [13.0, 4.0], [13.0, 7.0], [10.0, 7.0]]
    s = Scenario(
        "rendezvous", [[3.0, 3.0], [3.0, 3.0], [25.0, 25.0]], [[5.0, 25.0], [25.0, 5.0]],
        ["range"] * 3, workspace=30.0, closed=[False, True], obstacles=[square], max_steps=4,
    )  # fmt: skip
    trace = trial_trace(s, simulate(s, "rules-first", seed=0))
    path = tmp_path / "trace.json"
    path.write_text(json.dumps(trace))
    assert main(["view", str(path), "-o", str(tmp_path / "p.html")]) == 0
    browser.open(tmp_path / "p.html", "window.epistemicaView")
    assert browser.js("document.querySelectorAll('#map-0 polygon.obstacle').length") == 1
    closed = "[...document.querySelectorAll('polygon.goal.closed')].map(g => g.dataset.name)"
    assert browser.js(closed) == ["g2"]
    assert "g2 (closed)" in _texts(browser, "#knowledge-0 th")
    # Two robots at one place: the second is a wider ring around the first.
    stacked = browser.js(
        "[...document.querySelectorAll('circle.robot')].map(c => [c.dataset.robot, "
        "+c.getAttribute('r'), c.classList.contains('stacked')])"
    )
    assert stacked[1][0] == "r2" and stacked[1][2] and stacked[1][1] > stacked[0][1]
    assert not stacked[0][2] and not stacked[2][2]
    # Axes in metres and a scale bar; the set plot has tick labels on both axes.
    assert {"0", "10", "20", "30"} <= set(_texts(browser, "#map-0 text.tick.x"))
    assert {"0", "10", "20", "30"} <= set(_texts(browser, "#map-0 text.tick.y"))
    assert _texts(browser, "#map-0 .scale-bar text") == ["10 m"]  # one tick apart
    assert _texts(browser, "#sets-0 text.tick.x")[0] == "0"
    assert len(_texts(browser, "#sets-0 text.tick.y")) >= 2


def test_a_chosen_robots_model_of_its_teammates_is_shown(browser, compared):
    page, traces, trials = compared
    browser.open(page, "window.epistemicaView")
    step = trials[1].steps // 2
    browser.js(f"window.epistemicaView.setStep({step})")
    browser.js(
        "(s => { s.value = '1'; s.dispatchEvent(new Event('change')); })"
        "(document.querySelector('#model-robot-1'))"
    )
    rows = browser.js(
        "[...document.querySelectorAll('#model-1 tr[data-robot]')].map(r => r.dataset.robot)"
    )
    assert rows == ["r1", "r3"]
    known = trials[1].known_goals[min(step, trials[1].steps - 1)]
    cells = _texts(browser, "#model-1 td.goal-cell")
    goals = range(len(traces[1]["goals"]))
    assert cells == ["✓" if known[1, j, g] else "✗" for j in (0, 2) for g in goals]
    sets = _texts(browser, "#model-1 td.sets")
    modelled = trials[1].modelled[min(step, trials[1].steps - 1), 1]
    assert sets == [str(modelled[j]) if modelled[j] > 0 else "not computed" for j in (0, 2)]


def test_nested_lines_are_drawn_beside_equal_lines_and_named_in_a_legend(browser, compared):
    page, traces, trials = compared
    browser.open(page, "window.epistemicaView")
    for k, trial in enumerate(trials):
        f = focus_robot(traces[k])
        robots = traces[k]["robots"]
        drawn = browser.js(
            f"[...document.querySelectorAll('#sets-{k} polyline')].map(p => [p.dataset.line, "
            "p.getAttribute('stroke-dasharray'), p.getAttribute('points').trim().split(' ')"
            ".map(q => +q.split(',')[1])])"
        )
        names = [f"{r}'s own" for r in robots]
        names += [f"{robots[f]}'s model of {r}'s" for j, r in enumerate(robots) if j != f]
        assert [d[0] for d in drawn] == names
        assert [bool(d[1]) for d in drawn] == [False] * 3 + [True] * 2  # models dashed
        values = [trial.considered[:, i] for i in range(3)]
        values += [trial.modelled[:, f, j] for j in range(3) if j != f]
        coinciding = 0
        for a in range(len(drawn)):
            for b in range(a + 1, len(drawn)):
                equal = values[a] == values[b]
                gap = np.abs(np.subtract(drawn[a][2], drawn[b][2]))[equal]
                assert (gap >= 2.0).all(), (drawn[a][0], drawn[b][0])
                coinciding += int(equal.sum()) if b >= 3 > a else 0
                # where the values differ the order on screen follows them (y grows down)
                apart = np.abs(values[a] - values[b]) >= 1
                assert (np.sign(np.subtract(drawn[a][2], drawn[b][2])[apart])
                        == -np.sign(values[a] - values[b])[apart]).all()  # fmt: skip
        assert coinciding > 0  # a model equal to a teammate's own set: drawn beside it
        legend = _texts(browser, f"#sets-legend-{k} span[data-line]")
        assert [t.strip() for t in legend] == names


def test_the_focus_robot_and_a_certain_first_belief_are_explained(browser, compared):
    page, traces, trials = compared
    browser.open(page, "window.epistemicaView")
    for k, trial in enumerate(trials):
        known = trial.known_goals  # (T, n, n, m), from the simulation itself
        own = np.stack([known[:, i, i] for i in range(3)], axis=1)  # (T, n, m)
        private = own[:, :, None, :] & ~known  # i knows g, takes j not to
        counts = private.sum(axis=(0, 2, 3))
        f = int(np.argmax(counts))
        assert traces[k]["robots"][f] == "r1"  # who alone knows of g4
        goals = [traces[k]["goals"][g] for g in np.flatnonzero(private[:, f].any(axis=(0, 1)))]
        steps = int(private[:, f].sum(axis=0).max())
        text = browser.js(f"document.querySelector('#focus-why-{k}').textContent")
        assert text == (
            f"r1 is shown first: it knows of {' and '.join(goals)} and takes r2 and r3 not to "
            f"know of it (on {steps} of {trial.steps} steps)"
        )
        assert browser.js(f"document.querySelector('#model-robot-{k}').value") == str(f)
        # A belief of 1.00 at step 0, before any event: true (computed by the trial) and
        # explained beside the table.
        browser.js("window.epistemicaView.setStep(0)")
        certain = trial.goal_belief[0].max() > 0.995
        assert ("1.00" in _texts(browser, f"#belief-{k} td")) == certain
        note = browser.js(f"document.querySelector('#belief-why-{k}').textContent")
        assert "step 0" in note and "prior" in note and "1.00" in note
