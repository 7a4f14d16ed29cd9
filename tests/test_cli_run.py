"""``epistemica run`` and ``epistemica check`` on mission files."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest

from epistemica.cli import main
from epistemica.del_ import Observation, parse_formula
from epistemica.mission import load_mission
from epistemica.sim import simulate
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.worlds import fact_mask

ROOT = Path(__file__).resolve().parents[1]

TINY = """\
mission allocation
robot a: range at random
robot b: bearing at random
goal x at random
goal y at random
event settle seen by nearby
sensing range 12
simulate trials 3 seed 5 steps 60 levels zero, convention, rules_third
"""


@pytest.fixture
def tiny(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "tiny.epi"
    path.write_text(TINY)
    return path


def test_run_writes_rows_table_figure_and_animation(tiny, capsys, few_frames):
    assert main(["run", str(tiny)]) == 0
    out = capsys.readouterr().out
    for level in ("zero", "convention", "rules-third"):
        assert f" {level} " in out
    db = Path("runs/tiny.sqlite")
    rows = sqlite3.connect(db).execute("SELECT reasoning, seed FROM trials").fetchall()
    assert sorted(rows) == sorted(
        (lv, s) for lv in ("zero", "convention", "rules-third") for s in (5, 6, 7)
    )
    assert Path("runs/tiny.png").stat().st_size > 0
    assert Path("runs/tiny.gif").read_bytes()[:3] == b"GIF"
    # The page draws the animated trial beside a level that failed on the same seed (else
    # the level before it).
    html = Path("runs/tiny.html").read_text()
    data = json.loads(html.split('type="application/json">')[1].split("</script>")[0])
    shown = [(t["level"], t["trace"]["seed"], t["trace"]["success"]) for t in data["trials"]]
    seed = shown[0][1]
    failed = {lv for lv, s in rows if s == seed} - {
        lv
        for lv, s, ok in sqlite3.connect(db).execute("SELECT reasoning, seed, success FROM trials")
        if s == seed and ok
    }
    assert shown[0][0] == "rules-third" and shown[1][1] == seed and len(shown) == 2
    expected = [lv for lv in ("zero", "convention") if lv in failed] or ["convention"]
    assert shown[1][0] == expected[-1] and shown[1][2] == (shown[1][0] not in failed)


def test_run_again_resumes_and_runs_nothing(tiny, capsys):
    assert main(["run", str(tiny), "--no-gif"]) == 0
    capsys.readouterr()
    assert main(["run", str(tiny), "--no-gif"]) == 0
    out = capsys.readouterr().out
    assert "0 trials run, 9 already stored" in out


def test_an_explicit_out_is_never_added_to_silently(tiny, capsys):
    assert main(["run", str(tiny), "--no-gif", "--out", "mine.sqlite"]) == 0
    assert main(["run", str(tiny), "--no-gif", "--out", "mine.sqlite"]) == 2
    assert "already exists" in capsys.readouterr().err


def test_the_stored_rows_are_the_simulator_outcomes(tiny):
    assert main(["run", str(tiny), "--no-gif", "--trials", "2"]) == 0
    mission = load_mission(tiny)
    db = sqlite3.connect("runs/tiny.sqlite")
    for level, seed, success, steps in db.execute(
        "SELECT reasoning, seed, success, steps FROM trials"
    ):
        trial = simulate(mission.scenario(seed), level, seed=seed)
        assert (bool(success), steps) == (trial.success, trial.steps)


def test_several_missions_run_in_turn_each_to_its_own_file(tiny, capsys):
    other = tiny.with_name("other.epi")
    other.write_text(TINY.replace("levels zero, convention, rules_third", "levels zero"))
    assert main(["run", str(tiny), str(other), "--no-gif"]) == 0
    out = capsys.readouterr().out
    assert out.index("tiny.epi") < out.index("other.epi")
    for name, count in (("tiny", 9), ("other", 3)):
        db = sqlite3.connect(f"runs/{name}.sqlite")
        assert db.execute("SELECT COUNT(*) FROM trials").fetchone()[0] == count


def test_a_bad_second_mission_stops_before_any_trial(tiny, capsys):
    bad = tiny.with_name("bad.epi")
    bad.write_text(TINY.replace("goal y at random", "goal y at randm"))
    assert main(["run", str(tiny), str(bad), "--no-gif"]) == 2
    assert f"{bad}:5:" in capsys.readouterr().err
    assert not Path("runs/tiny.sqlite").exists()


def test_one_out_file_for_several_missions_is_refused(tiny, capsys):
    assert main(["run", str(tiny), str(tiny), "--out", "x.sqlite"]) == 2
    assert "--out" in capsys.readouterr().err


def test_bad_mission_exits_2_with_location(tmp_path, capsys):
    path = tmp_path / "bad.epi"
    path.write_text(TINY.replace("goal y at random", "goal y at randm"))
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}:5:" in err and "Traceback" not in err


def test_check_claims_of_a_mission(capsys):
    assert main(["check", str(ROOT / "specs" / "capacity.epi")]) == 0
    assert "3 passed, 0 failed" in capsys.readouterr().out


def test_check_after_steps_applies_the_trial_events(capsys):
    path = ROOT / "specs" / "sensing_radius.epi"
    mission = load_mission(path)
    trial = simulate(mission.scenario(0), "rules-third", seed=0)
    settles = [e for e in trial.events if e[1] == "settle"]
    assert settles, "the spec's first trial should show a settle event"
    step = max(e[0] for e in settles) + 1
    # Independently: the chains (i, j) of a fresh state fed the recorded settles only.
    knowledge = TeamKnowledge(mission.robots, mission.goals)
    for _, _, robot, goal, observers in settles:
        names = {mission.robots[i] for i in observers}
        fact = f"assigned({mission.robots[robot]}, {mission.goals[goal]})"
        knowledge.observe(Observation("settle", full=names, suggests=fact))
    rows = mission.configurations()
    for i, j in [(0, 2), (2, 0), (0, 1)]:
        for r, g in [(0, 0), (1, 1), (2, 2)]:
            fact = f"assigned(r{r + 1}, g{g + 1})"
            on = fact_mask(parse_formula(fact), rows, mission.robots, mission.goals)
            expected = bool(on[knowledge.possible((i, j), rows)].all())
            formula = f"B[r{j + 1}] {fact}"
            args = ["check", str(path), "--after", str(step), "--seed", "0", "--json"]
            code = main([*args, "--robot", f"r{i + 1}", "--formula", formula, "--expect", "true"])
            out = json.loads(capsys.readouterr().out)
            assert out["format"] == "epistemica-mission-check" and out["version"] == 1
            assert out["claims"][0]["holds"] == expected
            assert code == (0 if expected else 1)


# Allocation of three robots to three goals: every configuration needs every goal, and
# at step 2 everybody sees g2 close (issue 38, item 4).
_CLOSES_A_NEEDED_GOAL = """mission allocation
workspace 30
robot r1: range at (13, 12)
robot r2: range at (18, 10)
robot r3: bearing at (27, 27)
goal g1 at (4, 25)
goal g2 at (15, 14)
goal g3 at (26, 4)
event door_shuts {
    when step 2
    closes g2
    announces closed(g2)
    full robots if near(g2, 100)
}
check "g2 closed": K[r1] closed(g2)
simulate trials 1 seed 0 steps 20 levels rules_third
"""


def test_an_event_closing_a_goal_every_configuration_needs_is_a_located_error(tmp_path, capsys):
    path = tmp_path / "closes.epi"
    path.write_text(_CLOSES_A_NEEDED_GOAL)
    line = _CLOSES_A_NEEDED_GOAL.splitlines().index("event door_shuts {") + 1
    assert main(["check", str(path)]) == 1  # before the event: nobody knows g2 is closed
    capsys.readouterr()
    assert main(["check", str(path), "--after", "4"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{path}:{line}:7: error: after 4 steps of trial 0 no valid")
    assert "event 'door_shuts' closed g2 at step 2" in err and "Traceback" not in err
    assert main(["check", str(path), "--after", "1"]) == 1  # before step 2: a model


def test_after_and_robot_are_for_missions_only(capsys):
    spec = ROOT / "specs" / "puzzles" / "coin_toss.epi"
    assert main(["check", str(spec), "--after", "3"]) == 2
    assert "mission files" in capsys.readouterr().err


def test_check_a_mission_without_claims_says_so(capsys):
    assert main(["check", str(ROOT / "specs" / "multi_task.epi")]) == 0
    assert "no claims" in capsys.readouterr().out
