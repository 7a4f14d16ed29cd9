"""The HTML pages in a real headless Chromium: drawn content, play/pause/scrub, formula box.

Chromium is driven over the DevTools protocol on a pipe (``--remote-debugging-pipe``: no
port, no driver, no Python package). Without a Chromium executable (Debian's ``chromium``
package) the module is skipped, with the reason.
"""

from __future__ import annotations

import base64
import fcntl
import io
import json
import os
import random
import shutil
import subprocess
import tempfile
import time

import numpy as np
import pytest

from epistemica.cli import main
from epistemica.del_ import evaluate, load_spec
from epistemica.model_json import world_names
from epistemica.sim import Scenario, simulate
from epistemica.sim.study.palette import ROBOT_COLOURS, focus_robot
from epistemica.sim.study.trace import trial_trace

CHROMIUM = next(
    (p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None
)
pytestmark = pytest.mark.skipif(
    CHROMIUM is None, reason="no Chromium executable on PATH (Debian: apt-get install chromium)"
)
PIL = pytest.importorskip("PIL.Image")
SPECS = os.path.join(os.path.dirname(__file__), "..", "specs", "puzzles")


class Browser:
    """Headless Chromium with one page, commands sent as NUL-terminated JSON on fd 3."""

    def __init__(self) -> None:
        self.profile = tempfile.mkdtemp(prefix="epistemica-chromium-")
        to_child, self.commands = os.pipe()
        self.replies, from_child = os.pipe()

        def pipes_on_3_and_4():
            a = fcntl.fcntl(to_child, fcntl.F_DUPFD, 10)
            b = fcntl.fcntl(from_child, fcntl.F_DUPFD, 10)
            os.dup2(a, 3)
            os.dup2(b, 4)

        flags = "--headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
        flags += "--disable-background-networking --disable-component-update --disable-sync "
        flags += "--remote-debugging-pipe --window-size=1300,1000 --hide-scrollbars"
        self.process = subprocess.Popen(
            [CHROMIUM, *flags.split(), f"--user-data-dir={self.profile}", "about:blank"],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            pass_fds=(3, 4),
            preexec_fn=pipes_on_3_and_4,
        )
        os.close(to_child)
        os.close(from_child)
        self.buffer, self.next_id, self.session = b"", 0, None
        target = self.send("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.send("Target.attachToTarget", targetId=target, flatten=True)[
            "sessionId"
        ]
        self.send("Page.enable")

    def send(self, method: str, **params):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if self.session is not None and not method.startswith("Target."):
            message["sessionId"] = self.session
        os.write(self.commands, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            while b"\0" in self.buffer:
                raw, self.buffer = self.buffer.split(b"\0", 1)
                reply = json.loads(raw)
                if reply.get("id") == self.next_id:
                    if "error" in reply:
                        raise RuntimeError(f"{method}: {reply['error']}")
                    return reply.get("result", {})
            chunk = os.read(self.replies, 1 << 20)
            if not chunk:
                raise RuntimeError("Chromium closed the pipe")
            self.buffer += chunk
        raise TimeoutError(method)

    def js(self, expression: str):
        result = self.send("Runtime.evaluate", expression=expression, returnByValue=True)
        if "exceptionDetails" in result:
            raise RuntimeError(result["exceptionDetails"])
        return result["result"].get("value")

    def open(self, path, ready: str) -> None:
        self.send("Page.navigate", url=f"file://{os.path.abspath(path)}")
        self.wait(f"document.readyState === 'complete' && !!({ready})")

    def wait(self, condition: str, timeout: float = 10.0) -> None:
        deadline = time.monotonic() + timeout
        while not self.js(condition):
            if time.monotonic() > deadline:
                raise TimeoutError(condition)
            time.sleep(0.05)

    def click(self, selector: str, fraction: float = 0.5) -> None:
        """A real mouse click at ``fraction`` of the element's width, mid-height."""
        box = self.js(
            f"(() => {{ const r = document.querySelector({json.dumps(selector)})"
            ".getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; })()"
        )
        x, y = box[0] + fraction * box[2], box[1] + box[3] / 2
        for kind in ("mousePressed", "mouseReleased"):
            self.send("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left", clickCount=1)

    def screenshot(self) -> np.ndarray:
        data = base64.b64decode(self.send("Page.captureScreenshot", format="png")["data"])
        return np.asarray(PIL.open(io.BytesIO(data)).convert("RGB"), dtype=int)

    def close(self) -> None:
        self.process.terminate()
        try:
            self.process.wait(10)
        except subprocess.TimeoutExpired:
            self.process.kill()
        os.close(self.commands)
        os.close(self.replies)
        shutil.rmtree(self.profile, ignore_errors=True)


@pytest.fixture(scope="module")
def browser():
    b = Browser()
    yield b
    b.close()


@pytest.fixture(scope="module")
def trial_page(tmp_path_factory):
    """A 5-robot trial with a sensing range, its trace and its page."""
    s = Scenario.paper("rendezvous", 5, seed=2, max_steps=30, sensing_range=8.0)
    trace = trial_trace(s, simulate(s, "third", seed=2))
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
    header = browser.js("[...document.querySelectorAll('#belief th')].map(t => t.textContent)")
    assert header[1:6] == trace["goals"] and header[6:] == trace["robots"]
    # The map on the screen: not blank, and every robot's colour is drawn there.
    box = browser.js("(() => { const r = map.getBoundingClientRect(); "
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
    cells = browser.js("[...document.querySelectorAll('#belief td')].map(t => t.textContent)")
    decided = min(step, trace["steps"] - 1)
    expected = [f"{v:.2f}" for row in trace["goal_belief"][decided] for v in row]
    assert cells == expected
    assert f"step {step} of {trace['steps']}" in browser.js("document.body.innerText")
    # What a robot reads of its teammates (teammate models): the trace's most likely type.
    types = trace["teammate_types"]
    kept = [i for i in range(5) if any(None not in row for st in types for row in st[i])]
    reader = focus_robot(trace) if focus_robot(trace) in kept else kept[0]
    lines = browser.js("[...document.querySelectorAll('#reading div')].map(d => d.textContent)")
    shown = []
    for j, row in enumerate(trace["teammate_types"][decided][reader]):
        if j != reader and None not in row:
            k = row.index(max(row))
            shown.append(f"{trace['robots'][j]}: {trace['types'][k]} {row[k]:.2f}")
    assert lines == shown and shown


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
