"""Collaborative missions: the language (``mission collaborative``, ``task ... needs K``,
``when R heads to T``), the simulator of tasks found while exploring, and its levels."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica import SpecError
from epistemica.cli import main
from epistemica.del_ import parse_formula
from epistemica.del_.errors import InvalidArgumentError
from epistemica.mission import load_mission, parse_mission
from epistemica.run import mission_trials
from epistemica.sim import simulate
from epistemica.sim.engine.events import EventRule, ObserverRule, Trigger, World, fire
from epistemica.sim.engine.missions import distances
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.policies.collaborative_levels import (
    COLLABORATIVE_LEVELS,
    CollaborativePolicy,
)
from epistemica.sim.policies.collaborative_parameters import CollaborativeParameters
from epistemica.sim.policies.collaborative_sweep import Route, lanes, sweep
from epistemica.sim.study.store import read_rows
from epistemica.sim.study.sweep import run_trial
from epistemica.sim.study.trace import decode

SPECS = ["specs/collaborative/tasks_3.epi", "specs/collaborative/tasks_5.epi",
         "specs/collaborative/tasks_8.epi"]  # fmt: skip

HEADER = """mission collaborative
workspace 30
robot r1..r3: range at random
"""
EVENTS = """
event found(r in robots, t in tasks) {
    when r within 7 of t
    reveals t
    full robots if sees(r)
}
event heading(r in robots, t in tasks) {
    when r heads to t
    reveals t
    full robots if sees(r)
}
event done(t in tasks) {
    when t is reached
    closes t
    announces closed(t)
    full robots if sees(reachers)
}
"""


def _events():
    return parse_mission(
        HEADER + "task t1 at random needs 2\nsensing range 7\n" + EVENTS
    ).parts.events


# -- the language ------------------------------------------------------------------------


def test_shipped_missions_compile_with_their_needs():
    needs = {3: (2, 3, 2), 5: (2, 3, 2, 3, 2), 8: (2, 3, 2, 3, 2, 3)}
    for path in SPECS:
        m = load_mission(path)
        s = m.scenario(0)
        assert m.kind.name == "collaborative"
        assert s.needs == needs[len(m.robots)]
        # the documented default study; oracle-events is for analysis only
        assert m.study.levels == ("convention", "rules-first", "rules", "first", "third", "oracle")
        assert {r.trigger.kind for r in s.events} == {"within", "settles", "heads", "reached"}


def test_tasks_at_random_come_from_the_seed():
    m = load_mission(SPECS[0])
    a, b, c = m.scenario(4), m.scenario(4), m.scenario(5)
    assert np.array_equal(a.tasks, b.tasks) and np.array_equal(a.starts, b.starts)
    assert not np.array_equal(a.tasks, c.tasks)
    assert (a.tasks >= 1).all() and (a.tasks <= 29).all()  # 1 m borders of a 30 m square


@pytest.mark.parametrize(
    ("body", "line", "words"),
    [
        ("task t1 at random\n", 4, "says how many robots it needs"),
        ("task t1 at random needs 4\n", 4, "needs 4 robots, the team has 3"),
        ("task t1 at random needs 0\n", 4, "0 is outside [1"),
        ("goal g1 at random\n", 1, "declares tasks"),
        ("task t1 at random needs 2\nsimulate levels zero\n", 5, "unknown reasoning level"),
        ("task t1 at random needs 2\npolicy patience -3\n", 5, "patience"),
        ("task t1 at random needs 2\npolicy nonsense 3\n", 5, "unknown collaborative parameter"),
        ('task t1 at random needs 2\ncheck "c": K[r1] closed(t1)\n', 1, "no claims"),
    ],
)
def test_bad_collaborative_missions_are_located(body, line, words):
    with pytest.raises(SpecError) as info:
        parse_mission(HEADER + body, "bad.epi")
    assert words in info.value.message
    assert info.value.line == line


def test_needs_stays_out_of_multitask_missions():
    text = "mission multitask\nrobot r1: range at random\ntask t1 at random needs 2\n"
    with pytest.raises(SpecError, match="'needs' in a multitask mission"):
        parse_mission(text)


def test_heads_to_compiles_to_its_trigger():
    heading = next(r for r in _events() if r.name == "heading")
    assert heading.trigger == Trigger("heads", "r", "t")
    assert heading.reveals == ("t",)


def test_policy_lines_set_collaborative_parameters():
    m = parse_mission(HEADER + "task t1 at random needs 2\npolicy patience 30 seek false\n")
    assert m.parameters == CollaborativeParameters(patience=30, seek=False)


# -- the heading trigger ---------------------------------------------------------------


def test_heading_is_seen_by_the_robots_in_sight_of_the_mover():
    sees = (ObserverRule("robots", parse_formula("sees(r)")),)
    rule = EventRule("heading", (("r", "robots"), ("t", "goals")), Trigger("heads", "r", "t"),
                     reveals=("t",), full=sees)  # fmt: skip
    before = np.array([[0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [20.0, 0.0, 0.0]])
    now = before.copy()
    now[0, 0] += 1.0  # r1 moves towards t2; r2, r3 stand still
    visible = distances(now, now[:, :2]) <= 7.0
    world = World(1, now, before, np.array([[0.0, 20.0], [9.0, 0.0]]), np.ones(2, bool),
                  np.zeros(2, bool), visible, 7.0, 1.5, ("range",) * 3, ("r1", "r2", "r3"),
                  ("t1", "t2"), np.array([1, 1, -1]))  # fmt: skip
    (firing,) = fire(rule, world)  # r2 "heads" to t2 too but did not move
    assert firing.binding == {"r": "r1", "t": "t2"}
    assert firing.observation.full == {"r1", "r2"}  # r3 is 19 m away
    assert fire(rule, world._replace(heading=None)) == []  # no steering known: never fires


# -- the simulator -----------------------------------------------------------------------


def test_a_task_is_done_when_enough_robots_stand_at_it_at_once():
    s = CollaborativeScenario([[5, 5], [5, 6], [25, 25]], [[5, 7], [24, 25]], (2, 3),
                              workspace=30.0, sensing_range=7.0, events=_events())  # fmt: skip
    trial = simulate(s, "convention", seed=0)
    # t1: both robots start within 2 m and see it at once: done after the first step
    assert trial.tasks_done[0] == 1
    # t2 needs all three: never done before the step all three stand within 1.5 m of it
    near = distances(trial.trajectory.reshape(-1, 3), s.tasks).reshape(
        trial.trajectory.shape[0], 3, 2)[..., 1] <= s.completion_radius  # fmt: skip
    if trial.tasks_done[1] >= 0:
        assert near[trial.tasks_done[1]].all()
        assert not near[: trial.tasks_done[1]].all(axis=1).any()


def test_a_finder_seen_by_a_teammate_tells_it_and_one_out_of_sight_does_not():
    tasks, needs = [[5, 5]], (2,)
    seen = CollaborativeScenario([[5, 8], [5, 14.5], [28, 28]], tasks, needs,
                                 workspace=30.0, sensing_range=7.0, events=_events())  # fmt: skip
    unseen = seen.replace(starts=np.array([[5, 8, 0], [5, 20, 0], [28, 28, 0]]))
    a = simulate(seen, "rules-first", seed=0, parameters=None)
    b = simulate(unseen, "rules-first", seed=0)
    # r2 is 9.5 m from the task: it learns of it from the found event (it sees r1, 6.5 m)
    assert a.knows[0, 1, 0] and not b.knows[0, 1, 0]
    assert a.knowledge.knows_goals((0, 1))[0]  # r1 knows r2 saw it find the task
    assert b.knows[0, 0, 0]


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from(sorted(COLLABORATIVE_LEVELS)))
def test_what_a_robot_knows_comes_from_sight_or_an_observed_event(seed, level):
    m = load_mission(SPECS[0])
    s = m.scenario(seed).replace(max_steps=80)
    trial = simulate(s, level, seed, parameters=m.parameters)
    first = trial.knows.argmax(axis=0)  # (n, m) first step robot i knew task t
    news = level.startswith("oracle")  # every sighting and event reaches everyone
    gap = np.hypot(*(trial.trajectory[:, :, None, :2] - s.tasks[None, None]).transpose(3, 0, 1, 2))
    for i, t in zip(*np.nonzero(trial.knows.any(axis=0)), strict=True):
        step = first[i, t]
        in_sight = gap[step, i, t] <= s.sensing_range
        told = any(e[0] <= step and i in e[3] and s.task_names[t] in e[2] for e in trial.events)
        assert in_sight or told or (news and trial.knows[step, :, t].all())
    if news:  # everyone knows the same tasks
        assert (trial.knows == trial.knows[:, :1]).all()


def test_oracle_events_spreads_news_of_a_task_but_not_where_teammates_are(monkeypatch):
    # r3, 32 m from r1 and 7 m sight: only the oracle tells it where r1 is
    s = CollaborativeScenario([[5, 8], [5, 20], [28, 28]], [[5, 5]], (2,),
                              workspace=30.0, sensing_range=7.0, events=_events())  # fmt: skip
    views = []
    plan = CollaborativePolicy.plan
    monkeypatch.setattr(
        CollaborativePolicy, "plan", lambda self, view: views.append(view) or plan(self, view)
    )
    for level, where in (("rules", False), ("oracle-events", False), ("oracle", True)):
        trial = simulate(s.replace(max_steps=1), level, seed=0)
        assert trial.knows[0, :, 0].tolist() == [True, level != "rules", level != "rules"]
        assert (views[-1].last_seen[0, 2] == 0) == where  # what robot 1 knows of robot 3


def test_every_level_sees_the_same_world_on_a_seed():
    m = load_mission(SPECS[0])
    s = m.scenario(7).replace(max_steps=30)
    starts = {lv: simulate(s, lv, 7).trajectory[0] for lv in COLLABORATIVE_LEVELS}
    assert all(np.array_equal(v, starts["rules"]) for v in starts.values())


def test_bad_scenarios_and_parameters_are_refused():
    with pytest.raises(InvalidArgumentError, match="needs"):
        CollaborativeScenario([[0, 0], [1, 1]], [[5, 5]], (3,))
    with pytest.raises(InvalidArgumentError, match="finite"):
        CollaborativeScenario([[0, np.nan]], [[5, 5]], (1,))
    with pytest.raises(InvalidArgumentError, match="sensing_range"):
        CollaborativeScenario([[0, 0]], [[5, 5]], (1,), sensing_range=0.0)
    with pytest.raises(InvalidArgumentError, match="unknown collaborative parameter"):
        CollaborativeParameters().replace(speed=3)
    with pytest.raises(InvalidArgumentError, match="unknown collaborative level"):
        simulate(CollaborativeScenario([[0, 0]], [[5, 5]], (1,)), "zero")


def test_lanes_cover_the_workspace():
    xs = lanes(40.0, 8.0, 2.0)  # at most 16 m apart: three lanes, 13.3 m apart
    assert np.allclose(xs, [20 / 3, 20, 100 / 3])
    assert lanes(10.0, 8.0, 2.0).tolist() == [5.0]
    for w, r, f in [(30.0, 7.0, 1.6), (50.0, 10.0, 1.6), (40.0, 8.0, 1.0)]:
        x = lanes(w, r, f)  # every point of [0, w] within f * r / 2 of a lane
        grid = np.linspace(0, w, 101)
        assert (np.abs(grid[:, None] - x[None]).min(axis=1) <= f * r / 2 + 1e-9).all()


@pytest.mark.parametrize("spec", SPECS)
def test_the_sweep_sees_every_point_but_the_corners(spec):
    # lanes end half a lane spacing from the edges (docs/simulation.md): the corner squares
    # of that side may be out of sight, and nothing else is
    s = load_mission(spec).scenario(0)
    w, r = s.workspace, s.sensing_range
    route = Route(sweep(s, 0, 2.0))
    grid = np.stack(np.meshgrid(*[np.linspace(0, w, 61)] * 2), axis=-1).reshape(-1, 2)
    unseen = np.array([route.gap(p) for p in grid]) > r + 1e-9
    half = w / (2 * len(lanes(w, r, 2.0)))
    edge = np.minimum(grid, w - grid)  # distance to the nearer edge, per axis
    assert (edge[unseen] < half).all(axis=1).all()  # only in the corner squares
    assert unseen.any() == (half * np.sqrt(2) > r)  # and there once the corner is too far


def test_check_on_a_collaborative_mission_is_a_clean_error(capsys):
    from epistemica.cli import main

    code = main(["check", SPECS[0], "--formula", "K[r1] closed(t1)"])
    assert code == 2
    assert "collaborative mission has no explicit model" in capsys.readouterr().err


def _small(tmp_path, steps=60):
    """tasks_3.epi with a step limit short enough for a test (a new text: a new study)."""
    text = (Path(__file__).resolve().parents[1] / SPECS[0]).read_text()
    path = tmp_path / "small.epi"
    path.write_text(text.replace("steps 400", f"steps {steps}"))
    return str(path)


def test_run_stores_collaborative_trials_and_resumes(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = _small(tmp_path)
    args = ["run", path, "--trials", "2", "--levels", "rules-first,rules", "--no-gif"]
    assert main(args) == 0
    first = capsys.readouterr().out
    rows = read_rows(tmp_path / "runs" / "small.sqlite")
    assert len(rows) == 4 and "4 trials run, 0 already stored" in first
    m = load_mission(path)
    for row in rows:  # each row is the trial simulated again, independently
        scenario, seed = m.scenario(row["seed"]), row["seed"]
        trial = simulate(scenario, row["reasoning"], seed, parameters=m.parameters)
        assert (row["success"], row["steps"]) == (int(trial.success), trial.steps)
        assert row["completion_step"] == trial.completion_step
        assert row["mission"] == "collaborative" and (row["robots"], row["goals"]) == (3, 3)
    mean = np.mean([r["steps"] for r in rows if r["reasoning"] == "rules" and r["success"]])
    if not np.isnan(mean):  # the table is the stored rows'
        assert f"{mean:.1f}" in first
    assert main([*args[:3], "3", *args[4:]]) == 0  # one more seed: only its trials run
    assert "2 trials run, 4 already stored" in capsys.readouterr().out
    assert len(read_rows(tmp_path / "runs" / "small.sqlite")) == 6


def test_a_stored_collaborative_trace_is_the_trial(tmp_path):
    m = load_mission(_small(tmp_path, steps=80))
    spec = mission_trials(m, ["rules"], 1, seed=3)[0]
    row = run_trial(spec)
    trace = decode(row["trace"])
    trial = simulate(m.scenario(3), "rules", 3, parameters=m.parameters)
    assert trace["kind"] == "collaborative" and trace["steps"] == trial.steps
    assert np.allclose(trace["poses"], trial.trajectory, atol=0.006)
    assert trace["tasks_known"] == trial.knows.astype(int).tolist() and "knows" not in trace
    assert trace["tasks_done"] == trial.tasks_done.tolist()
    assert trace["needs"] == list(m.scenario(3).needs)
    names = m.robots + m.goals
    for (step, name, args, observers), event in zip(trace["events"], trial.events, strict=True):
        assert (step, name, observers) == (event[0], event[1], list(event[3]))
        assert list(event[2]) == args and all(a in names for a in args)


def test_sweep_stores_a_collaborative_mission(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = _small(tmp_path)
    out = ["--out", "x.sqlite", "--reasoning", "convention"]
    assert main(["sweep", "--mission", path, "--trials", "1", *out]) == 0
    assert main(["sweep", "--mission", path, "--trials", "2", "--resume", *out]) == 0
    rows = read_rows(tmp_path / "x.sqlite")
    assert sorted(r["seed"] for r in rows) == [0, 1]
    assert "1 trials run, 1 already stored" in capsys.readouterr().out
    assert main(["sweep", "--mission", path, "--trials", "1", "--reasoning", "zero",
                 "--out", "y.sqlite"]) == 2  # fmt: skip
    assert "unknown collaborative level" in capsys.readouterr().err


def test_view_of_a_collaborative_result_replays_it(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["run", _small(tmp_path, 20), "--trials", "1", "--levels", "rules-first",
                 "--no-gif"]) == 0  # fmt: skip
    assert main(["view", "runs/small.sqlite", "-o", "v.html"]) == 0
    html = (tmp_path / "v.html").read_text()
    assert '"kind":"collaborative"' in html and '"panels":["targets"' in html
    assert "Traceback" not in capsys.readouterr().err


def test_a_backed_waiter_waits_longer():
    # r1 and r2 find a 3-robot task together (each sees the other: both know that both
    # know); r3 is far away. r1, the nearer, waits while r2 is out for helpers: it gives up
    # after backed_patience steps, not patience (news of a knower, `rejoin`, is left out:
    # it would renew the patience when r2 comes back; so is `seek_limit`, which would
    # bring r2 back to wait after 20 steps; and `fetch_together`, with which r1, seen by
    # nobody else at the task, would go with r2).
    s = CollaborativeScenario([[5, 5, 0], [7, 5, 0], [45, 45, 0]], [[6, 8]], (3,),
                              workspace=50.0, sensing_range=7.0, max_steps=170,
                              events=_events())  # fmt: skip
    waited = {}
    for backed in (60, 150):
        trial = simulate(
            s,
            "rules",
            0,
            parameters=CollaborativeParameters(
                backed_patience=backed, rejoin=False, seek_limit=0, fetch_together=False
            ),
        )
        at_task = trial.steer_to[:, 0] == 0
        waited[backed] = int(np.argmin(at_task))  # the first step r1 steers elsewhere
        assert at_task[: waited[backed]].all() and not trial.success
    assert waited[60] >= 60 and waited[150] >= waited[60] + 20
