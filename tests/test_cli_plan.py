"""``epistemica plan``: plans, explanations, JSON, exit codes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from epistemica.cli import main

MUDDY = str(Path(__file__).resolve().parents[1] / "specs" / "puzzles" / "muddy_children.epi")

# The only shortest plan: "nobody knows" before the father teaches nothing, and after the
# father the three muddy children need two rounds of "nobody knows" (published answer).
MUDDY_PLAN = ["father", "nobody_knows", "nobody_knows"]


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("search", ["bfs", "astar"])
def test_muddy_children_plan(capsys, search):
    code, out, err = run(capsys, "plan", MUDDY, "--search", search)
    assert code == 0, err
    steps = [line.split(". ", 1)[1] for line in out.splitlines() if line.startswith("  ")]
    assert steps == MUDDY_PLAN
    assert "validated" in out


def test_a_search_over_the_memory_budget_exits_2_naming_what_it_needs(capsys):
    """--memory-budget covers the states the search stores: a budget that lets the model
    be listed but not the states kept is refused cleanly, with the budget it would need."""
    code, out, err = run(capsys, "plan", MUDDY, "--memory-budget", "0.0000005")
    assert code == 2 and not out
    assert "distinct states of the search needs about" in err
    assert "over the memory budget of 536 bytes" in err  # 0.0000005 GiB
    assert "--memory-budget GIB" in err and "Traceback" not in err


def test_greedy_finds_a_valid_plan(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--search", "greedy", "--json")
    data = json.loads(out)
    assert code == 0 and data["valid"] and data["plan"][-2:] == ["nobody_knows", "nobody_knows"]


def test_plan_json_and_explain(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--json", "--explain")
    data = json.loads(out)
    assert code == 0
    assert data["plan"] == MUDDY_PLAN and data["length"] == 3 and data["valid"] is True
    assert data["goal"] == "K[c1] m1 & K[c2] m2 & K[c3] m3"
    # One description per state: initial plus one per step. The muddy children's
    # surviving worlds (after contraction): 8, then 7 (>= 1 muddy), 4 (>= 2), 1.
    assert [s.split(" ", 1)[0] for s in data["states"]] == ["8", "7", "4", "1"]


def test_explain_text_marks_the_designated_world(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--explain")
    assert code == 0
    assert "initial state:" in out
    assert "* w7  {m1, m2, m3}" in out  # the actual world of the initial model
    assert "c1: {w0, w4}" in out  # c1 confuses the worlds that differ in m1 only


def test_depth_bound_too_small_exits_1(capsys):
    code, out, _ = run(capsys, "plan", MUDDY, "--max-depth", "2")
    assert code == 1 and "no plan within the search bound" in out


def test_impossible_goal_exits_1(capsys, tmp_path):
    path = tmp_path / "never.epi"
    path.write_text("agents a\natoms p\nactual {}\naction tell: public p\ngoal K[a] p\n")
    code, out, _ = run(capsys, "plan", str(path))
    # p is false and nothing changes it, so no plan exists (the search space is finite).
    assert code == 1 and "no plan exists" in out


def test_spec_without_goal_exits_2(capsys, tmp_path):
    path = tmp_path / "nogoal.epi"
    path.write_text("agents a\natoms p\naction tell: public p\n")
    code, _, err = run(capsys, "plan", str(path))
    assert code == 2 and "no goal" in err and "hint:" in err and "Traceback" not in err


@pytest.mark.parametrize("depth", ["-1", "x", "1.5"])
def test_bad_max_depth_exits_2(capsys, depth):
    with pytest.raises(SystemExit) as info:
        main(["plan", MUDDY, "--max-depth", depth])
    assert info.value.code == 2
    assert "non-negative integer" in capsys.readouterr().err


def test_unknown_search_exits_2(capsys):
    with pytest.raises(SystemExit) as info:
        main(["plan", MUDDY, "--search", "dfs"])
    assert info.value.code == 2


# -- implicit coordination -----------------------------------------------------------------

TWO_ROBOTS = str(
    Path(__file__).resolve().parents[1] / "specs" / "planning" / "two_robots_implicit.epi"
)
# Worked out in the spec's comments: r1 knows its task (g1) and moves first, which tells
# r2 where to go; the reverse order works in the actual world but r2 cannot know it does.
COORDINATED = ["go_r1_g1", "go_r2_g2"]
UNCOORDINATED = ["go_r2_g2", "go_r1_g1"]


def steps_of(out):
    return [line.split(". ", 1)[1].split("  ")[0] for line in out.splitlines() if ". go_" in line]


def test_implicit_plan_is_the_coordinated_order(capsys):
    code, out, err = run(capsys, "plan", TWO_ROBOTS, "--implicit")
    assert code == 0, err
    assert steps_of(out) == COORDINATED
    assert "coordinated: every owner knows" in out
    # Plain BFS prefers the other order, which is valid but not coordinated.
    code, out, _ = run(capsys, "plan", TWO_ROBOTS)
    assert code == 0 and steps_of(out) == UNCOORDINATED


def test_implicit_explain_names_the_acting_agent(capsys):
    code, out, _ = run(capsys, "plan", TWO_ROBOTS, "--implicit", "--explain")
    assert code == 0
    assert "  1. go_r1_g1  (by r1)" in out and "  2. go_r2_g2  (by r2)" in out
    assert "initial state:" in out


def test_verify_reports_why_a_plan_is_not_coordinated(capsys):
    code, out, _ = run(
        capsys, "plan", TWO_ROBOTS, "--implicit", "--verify", ",".join(UNCOORDINATED)
    )
    assert code == 1
    assert "plan go_r2_g2, go_r1_g1: not implicitly coordinated" in out
    # Step 2 belongs to r1, whose move is not executable where r1's task is g2: a world
    # that r2 could not rule out when it moved at step 1.
    assert "step 2 (go_r1_g1): r1 does not know that go_r1_g1 is applicable" in out
    assert "at step 1 r2 could not tell" in out


def test_verify_json_gives_step_agent_and_kind(capsys):
    argv = ["plan", TWO_ROBOTS, "--implicit", "--json", "--verify", "go_r2_g2, go_r1_g1"]
    code, out, _ = run(capsys, *argv)
    data = json.loads(out)
    assert code == 1 and data["coordinated"] is False and data["plan"] == UNCOORDINATED
    assert (data["step"], data["agent"], data["action"], data["kind"]) == (
        2, "r1", "go_r1_g1", "not-applicable",
    )  # fmt: skip
    code, out, _ = run(capsys, "plan", TWO_ROBOTS, "--implicit", "--json", "--verify",
                       ",".join(COORDINATED))  # fmt: skip
    assert code == 0 and json.loads(out)["coordinated"] is True


def test_verify_without_implicit_only_validates(capsys):
    code, out, _ = run(capsys, "plan", TWO_ROBOTS, "--verify", ",".join(UNCOORDINATED))
    assert code == 0 and "go_r1_g1: valid" in out
    code, out, _ = run(capsys, "plan", TWO_ROBOTS, "--verify", "go_r2_g2")
    assert code == 1 and "not valid" in out


def test_implicit_json_lists_owners(capsys):
    code, out, _ = run(capsys, "plan", TWO_ROBOTS, "--implicit", "--json")
    data = json.loads(out)
    assert code == 0 and data["plan"] == COORDINATED and data["owners"] == ["r1", "r2"]
    assert data["coordinated"] is True and data["complete"] is True


def test_schema_owners_and_arguments_in_verify(capsys, tmp_path):
    path = tmp_path / "doors.epi"
    path.write_text(
        "agents a, b\natoms open(a), open(b)\nobserves a, b: open(a), open(b)\nactual {}\n"
        "action open(i in agents) by i: assign open(i) := true\ngoal open(a) & open(b)\n"
    )
    code, out, _ = run(capsys, "plan", str(path), "--implicit", "--json")
    data = json.loads(out)
    assert code == 0 and data["length"] == 2 and sorted(data["owners"]) == ["a", "b"]
    code, out, _ = run(capsys, "plan", str(path), "--implicit", "--verify", "open(b),open( a )")
    assert code == 0 and "plan open(b), open(a): implicitly coordinated" in out


def test_implicit_needs_owners(capsys):
    code, _, err = run(capsys, "plan", MUDDY, "--implicit")
    assert code == 2 and "has no owner" in err and "by AGENT" in err and "Traceback" not in err


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--verify", "go_r1_g1,go_r2_g3"], "did you mean 'go_r2_g2'?"),
        (["--verify", "go_r1_g1,,go_r2_g2"], "cannot read the plan"),
        (["--search", "astar"], "breadth-first only"),
    ],
)
def test_implicit_bad_input_exits_2(capsys, extra, message):
    code, _, err = run(capsys, "plan", TWO_ROBOTS, "--implicit", *extra)
    assert code == 2 and message in err and "hint:" in err


# One agent flips p on and off; `use` needs p and makes q true (the goal).
SWITCH = """\
agents a
atoms p, q
observes a: p, q
actual {}
action on by a: assign p := true
action off by a: assign p := false
action use by a {
    pre p
    effect q := true
    full a
}
goal q
"""


@pytest.mark.parametrize(
    ("plan", "step", "inapplicable"),
    [
        ("use", 1, True),  # p is false at first
        ("on,off,use", 3, True),  # p is false again when `use` comes
        ("on,off", 2, False),  # every step runs, the goal fails: charged to the last step
    ],
)
def test_plan_steps_count_from_1_in_every_output(capsys, tmp_path, plan, step, inapplicable):
    path = tmp_path / "switch.epi"
    path.write_text(SWITCH)
    outputs = []
    for implicit in ([], ["--implicit"]):
        code, out, _ = run(capsys, "plan", str(path), *implicit, "--verify", plan, "--json")
        assert code == 1
        outputs.append(json.loads(out)["step"])
        code, out, _ = run(capsys, "plan", str(path), *implicit, "--verify", plan)
        if inapplicable:  # both texts name the step that cannot happen
            assert f"step {step} (use)" in out
    assert outputs == [step, step]


def test_found_plans_are_listed_from_1(capsys, tmp_path):
    path = tmp_path / "switch.epi"
    path.write_text(SWITCH)
    for implicit in ([], ["--implicit"]):
        code, out, _ = run(capsys, "plan", str(path), *implicit)
        assert code == 0
        assert "  1. on" in out and "  2. use" in out and "  0." not in out


def test_irrelevant_atoms_change_neither_the_plan_nor_the_validated_states(capsys, tmp_path):
    """The command line validates on the states the search sees (issue 21: grapevine with
    8 atoms nobody observes used to spend minutes contracting 16,384-world states)."""
    source = Path(MUDDY).parents[1] / "planning" / "grapevine.epi"
    lines = source.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("atoms "))
    lines.insert(at + 1, "atoms " + ", ".join(f"junk{j}" for j in range(8)))
    padded = tmp_path / "grapevine_padded.epi"
    padded.write_text("\n".join(lines) + "\n")
    code, out, _ = run(capsys, "plan", str(source), "--json", "--explain")
    plain = json.loads(out)
    code_padded, out, _ = run(capsys, "plan", str(padded), "--json", "--explain")
    data = json.loads(out)
    assert code == code_padded == 0
    assert data["plan"] == plain["plan"] and data["valid"]
    assert data["states"] == plain["states"]


PLANNING = Path(MUDDY).parents[1] / "planning"


def test_backends_give_the_same_plan(capsys):
    path = str(PLANNING / "selective_communication.epi")
    _, out, _ = run(capsys, "plan", path, "--json", "--backend", "explicit")
    explicit = json.loads(out)
    code, out, _ = run(capsys, "plan", path, "--json", "--backend", "symbolic")
    symbolic = json.loads(out)
    assert code == 0 and symbolic["valid"] and symbolic["backend"] == "symbolic"
    assert explicit["backend"] == "explicit" and symbolic["plan"] == explicit["plan"]
    code, _, err = run(capsys, "plan", path, "--backend", "symbolic", "--implicit")
    assert code == 2 and "Kripke models only" in err


def test_policy_tree_and_its_verification(capsys, tmp_path):
    path = str(PLANNING / "two_robots_implicit.epi")
    code, out, _ = run(capsys, "plan", path, "--implicit", "--policy", "--perspective", "r2")
    assert code == 0
    assert "  r1, when it knows target1: go_r1_g1\n    r2: go_r2_g2\n" in out
    assert "  r1, when it knows ~target1: go_r1_g2\n    r2: go_r2_g1\n" in out
    code, out, _ = run(
        capsys, "plan", path, "--implicit", "--policy", "--perspective", "r2", "--json"
    )
    saved = tmp_path / "policy.json"
    saved.write_text(out)
    assert json.loads(out)["depth"] == 2 and json.loads(out)["decisions"] == 4
    verify = ["plan", path, "--implicit", "--policy", "--perspective", "r2", "--verify"]
    code, out, _ = run(capsys, *verify, str(saved))
    assert code == 0 and "implicitly coordinated" in out
    code, out, _ = run(capsys, *verify, "go_r1_g1,go_r2_g2")  # no branch: fails for ~target1
    assert code == 1 and "does not know that go_r1_g1 is applicable" in out


def test_policy_where_no_sequential_plan_exists(capsys):
    path = str(PLANNING / "policies" / "tiger_signal.epi")
    code, _, _ = run(capsys, "plan", path, "--implicit")
    assert code == 1
    code, out, _ = run(capsys, "plan", path, "--implicit", "--policy")
    assert code == 0 and "l, when it knows tiger_left: go_right" in out


@pytest.mark.parametrize(
    "argv",
    [
        ["--policy"],  # needs --implicit
        ["--implicit", "--perspective", "r2"],  # needs --policy
        ["--implicit", "--policy", "--perspective", "nobody"],
        ["--implicit", "--policy", "--verify", "missing.json"],
    ],
)
def test_policy_options_misused_exit_2(capsys, argv):
    code, _, err = run(capsys, "plan", str(PLANNING / "two_robots_implicit.epi"), *argv)
    assert code == 2 and "hint:" in err


def test_verify_on_the_symbolic_backend(capsys):
    path = str(PLANNING / "selective_communication.epi")
    argv = ["plan", path, "--backend", "symbolic", "--verify"]
    code, out, _ = run(capsys, *argv, "right,sense,right,right,shout")
    assert code == 0 and "valid" in out
    code, out, _ = run(capsys, *argv, "sense,right")
    assert code == 1 and "step 1 (sense) is not applicable" in out
    code, out, _ = run(capsys, *argv, "right,sense", "--explain")
    assert code == 1 and "variables, atoms: at1, at2, at3, at4, secret" in out
