"""``epistemica show``: the model of a spec after some of its actions, as text, DOT, JSON."""

from __future__ import annotations

import json
from itertools import combinations
from pathlib import Path

import pytest
from hypothesis import given, settings

from epistemica.cli import main
from epistemica.del_ import bisimilar
from epistemica.model_json import model_from_json, model_to_json, world_names

from epistemic_strategies import explicit, models

ROOT = Path(__file__).resolve().parents[1]
MUDDY = str(ROOT / "specs" / "puzzles" / "muddy_children.epi")

# Explicit worlds, so that the names to keep are the spec's own.
WEATHER = """\
agents ann, bob
atoms rain, wind
world sunny {}
world stormy {rain, wind}
world wet {rain}
partition ann: {sunny, stormy}, {wet}
partition bob: {sunny}, {stormy, wet}
designated stormy
action forecast: public rain
"""


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_muddy_children_after_the_father_as_json(capsys):
    code, out, _ = run(capsys, "show", MUDDY, "--after", "father", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["after"] == ["father"] and data["agents"] == ["c1", "c2", "c3"]
    assert data["atoms"] == ["m1", "m2", "m3"]
    # The father removes the clean world: the 7 non-empty valuations remain.
    atoms = {w["name"]: frozenset(w["atoms"]) for w in data["worlds"]}
    nonempty = {frozenset(c) for k in (1, 2, 3) for c in combinations(["m1", "m2", "m3"], k)}
    assert sorted(atoms.values(), key=sorted) == sorted(nonempty, key=sorted)
    assert [atoms[w] for w in data["designated"]] == [{"m1", "m2", "m3"}]
    # c1 confuses exactly the worlds that differ in m1 only (both still present).
    blocks = {frozenset(atoms[w] for w in b) for b in data["relations"]["c1"]["belief"]["blocks"]}
    expected = {frozenset({v, v | {"m1"}}) - {frozenset()} for v in nonempty if "m1" not in v}
    expected.add(frozenset({frozenset({"m1"})}))
    assert blocks == expected


def test_text_output_lists_worlds_and_partitions(capsys):
    code, out, _ = run(capsys, "show", MUDDY, "--after", "father nobody_knows")
    assert code == 0
    assert out.splitlines()[0].endswith("after father, nobody_knows")
    # After one round of "nobody knows" the worlds with one muddy child are gone: 4 remain.
    assert "4 worlds, 1 designated; agents c1, c2, c3" in out
    # Worlds keep their initial names (w7: all muddy), extended by the events applied.
    assert "* w7.announce.announce  {m1, m2, m3}" in out


def test_the_spec_s_world_names_are_kept_after_an_update(capsys, tmp_path):
    path = tmp_path / "weather.epi"
    path.write_text(WEATHER)
    code, out, _ = run(capsys, "show", str(path), "--after", "forecast", "--json")
    data = json.loads(out)
    assert code == 0
    assert [w["name"].split(".")[0] for w in data["worlds"]] == ["stormy", "wet"]
    assert data["designated"][0].startswith("stormy.")
    code, out, _ = run(capsys, "show", str(path))
    assert "* stormy  {rain, wind}" in out and "ann: {sunny, stormy} {wet}" in out


def test_dot_is_written_with_names(capsys, tmp_path):
    path = tmp_path / "weather.epi"
    path.write_text(WEATHER)
    dot = tmp_path / "out.dot"
    code, out, _ = run(capsys, "show", str(path), "--after", "forecast", "--dot", str(dot))
    assert code == 0 and f"wrote {dot}: 2 worlds" in out
    text = dot.read_text()
    assert text.startswith("digraph kripke {") and text.count("doublecircle") == 1
    assert 'label="stormy.' in text and 'label="wet.' in text and "(" not in text


def test_round_trip_of_a_shown_model_gives_the_same_model(capsys):
    from epistemica.cli.show import model_after
    from epistemica.del_ import load_spec

    original = model_after(load_spec(MUDDY), ["father", "nobody_knows"])
    code, out, _ = run(capsys, "show", MUDDY, "--after", "father,nobody_knows", "--json")
    back = model_from_json(json.loads(out))
    assert code == 0 and bisimilar(original, back)
    assert back.atoms == original.atoms and back.n_worlds == original.n_worlds
    assert model_to_json(back) == model_to_json(original)


def _same_up_to_names(model, back) -> None:
    names = world_names(model)
    worlds, valuation, belief, know = explicit(model)
    worlds2, valuation2, belief2, know2 = explicit(back)
    assert list(worlds2) == [names[w] for w in worlds]
    assert {names[w]: v for w, v in valuation.items()} == valuation2
    rename = lambda pairs: {(names[w], names[v]) for w, v in pairs}  # noqa: E731
    assert {a: rename(p) for a, p in belief.items()} == belief2
    assert {a: rename(p) for a, p in know.items()} == know2
    assert [names[w] for w in model.designated] == list(back.designated)
    assert back.atoms == model.atoms


@settings(max_examples=80, deadline=None)
@given(model=models(kind="kd45-s5") | models(kind="any") | models(kind="s5"))
def test_json_round_trip_on_random_models(model):
    data = json.loads(json.dumps(model_to_json(model)))
    back = model_from_json(data)
    _same_up_to_names(model, back)
    assert bisimilar(model, back)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--after", "fathr"], "did you mean 'father'?"),
        # After the father and two rounds every child knows: a third "nobody knows" is false.
        (["--after", "father " + "nobody_knows " * 3], "action 4 (nobody_knows) cannot happen"),
        (["--after", "father,,father"], "cannot read the plan"),
    ],
)
def test_bad_after_exits_2_with_a_hint(capsys, argv, message):
    code, out, err = run(capsys, "show", MUDDY, *argv)
    assert code == 2 and message in err and "hint:" in err and out == ""


def test_dot_and_json_exclude_each_other(capsys, tmp_path):
    with pytest.raises(SystemExit) as info:
        main(["show", MUDDY, "--json", "--dot", str(tmp_path / "m.dot")])
    assert info.value.code == 2 and "not allowed with" in capsys.readouterr().err


def test_reading_something_else_is_an_error():
    from epistemica.del_.errors import InvalidArgumentError

    with pytest.raises(InvalidArgumentError, match="not a model written by"):
        model_from_json({"worlds": []})
    with pytest.raises(InvalidArgumentError, match="malformed model object"):
        model_from_json({"format": "epistemica-kripke-1", "worlds": [{"atoms": []}]})


# -- large models: linear output, --limit, the symbolic backend, --where (issue 22) -----


def _muddy(tmp_path, n: int) -> str:
    atoms = [f"m{i}" for i in range(1, n + 1)]
    lines = [f"agents c1..c{n}", f"atoms m1..m{n}"]
    for i in range(1, n + 1):
        lines.append(f"observes c{i}: " + ", ".join(a for a in atoms if a != f"m{i}"))
    lines.append("actual {m1, m2}")
    path = tmp_path / f"muddy{n}.epi"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def test_json_of_a_large_model_lists_blocks_and_reads_back(capsys, tmp_path):
    """10 children, 1,024 worlds: each child's partition has 512 blocks of two worlds."""
    code, out, _ = run(capsys, "show", _muddy(tmp_path, 10), "--json")
    data = json.loads(out)
    assert code == 0 and len(data["worlds"]) == 1024
    for agent in data["agents"]:
        blocks = data["relations"][agent]["belief"]["blocks"]
        assert len(blocks) == 512 and {len(b) for b in blocks} == {2}
    back = model_from_json(data)
    assert back.n_worlds == 1024 and back.holds("~Kw[c1] m1 & K[c3] (m1 & m2)")


def test_limit_keeps_the_designated_world_and_is_not_read_back(capsys, tmp_path):
    code, out, _ = run(capsys, "show", _muddy(tmp_path, 10), "--json", "--limit", "5")
    data = json.loads(out)
    assert code == 0 and data["truncated"] and data["n_worlds"] == 1024
    names = [w["name"] for w in data["worlds"]]
    assert len(names) == 5 and data["designated"][0] in names
    shown = set(names)
    for relation in data["relations"].values():
        assert all(set(b) <= shown for b in relation["belief"]["blocks"])
    with pytest.raises(ValueError, match="truncated"):
        model_from_json(data)


def test_text_limit_lists_that_many_worlds(capsys, tmp_path):
    code, out, _ = run(capsys, "show", _muddy(tmp_path, 10), "--limit", "3")
    assert code == 0 and "1024 worlds" in out and "... 1023 more worlds not shown" in out


def test_symbolic_show_prints_vocabulary_law_and_observables(capsys):
    code, out, _ = run(capsys, "show", MUDDY, "--backend", "symbolic", "--after", "father")
    assert code == 0
    assert "knowledge structure: 3 atoms, 3 variables, 7 states, 1 designated" in out
    assert "vocabulary: m1, m2, m3" in out
    assert "c1: m2, m3" in out and "designated: {m1, m2, m3}" in out
    # the law has 7 satisfying valuations of 8: every one but all-clean
    law = next(line for line in out.splitlines() if "law:" in line)
    assert "~m1 & ~m2 & ~m3" not in law


def test_symbolic_show_of_forty_children_and_dot_refusal(capsys, tmp_path):
    path = _muddy(tmp_path, 40)
    code, out, _ = run(capsys, "show", path, "--json")
    data = json.loads(out)
    assert code == 0 and data["n_states"] == 2**40 and data["designated"] == [["m1", "m2"]]
    assert data["observables"]["c1"] == [f"m{i}" for i in range(2, 41)]
    code, _, err = run(capsys, "show", path, "--dot", str(tmp_path / "m.dot"))
    assert code == 2 and "knowledge structure" in err


@pytest.mark.parametrize("backend", ["explicit", "symbolic"])
def test_where_lists_the_worlds_on_both_backends(capsys, backend):
    code, out, _ = run(
        capsys, "check", MUDDY, "--formula", "m1 & m2", "--where", "--backend", backend, "--json"
    )
    data = json.loads(out)
    assert code == 0
    if backend == "explicit":
        listed = [set(w["atoms"]) for w in data["worlds"]]
    else:
        listed = [set(v) for v in data["valuations"]]
    assert sorted(map(sorted, listed)) == [["m1", "m2"], ["m1", "m2", "m3"]]


def test_where_is_capped_by_limit(capsys, tmp_path):
    path = _muddy(tmp_path, 30)  # symbolic: 2^29 states where m1 holds
    code, out, _ = run(capsys, "check", path, "--formula", "m1", "--where", "--limit", "4",
                       "--json")  # fmt: skip
    data = json.loads(out)
    assert code == 0 and data["holds"] and data["n_true"] == 2**29  # m1 is actual
    assert len(data["valuations"]) == 4 and data["truncated"]
    assert all("m1" in v for v in data["valuations"])


def test_dot_of_too_many_pairs_is_refused_and_limit_draws_a_part(capsys, tmp_path):
    """b sees nothing of 65,536 worlds: 2^32 pairs to draw; --limit 50 draws 50 worlds."""
    path = tmp_path / "blind.epi"
    path.write_text("agents a, b\natoms m1..m16\nobserves a: m1\n", encoding="utf-8")
    dot = tmp_path / "m.dot"
    code, _, err = run(capsys, "show", str(path), "--dot", str(dot))
    assert code == 2 and "more than 5,000,000 to draw" in err and "--limit" in err
    code, out, _ = run(capsys, "show", str(path), "--dot", str(dot), "--limit", "50")
    assert code == 0 and "(the first 50)" in out
    assert dot.read_text().count("[label=") == 50 + 2 * 50 * 50  # worlds, then a's and b's pairs
