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
    from epistemica.cli_show import model_after
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
