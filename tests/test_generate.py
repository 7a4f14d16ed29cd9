"""Generated missions (:mod:`epistemica.generate`, ``epistemica generate``): readable files
that compile, pass ``check`` and run; the same seed gives the same bytes; bad input exits 2."""

from __future__ import annotations

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.cli import main
from epistemica.cli.generate_arguments import FAMILY_NAMES
from epistemica.del_.errors import InvalidArgumentError
from epistemica.generate import FAMILIES, Options, generate, mission_text
from epistemica.mission import parse_mission
from epistemica.sim.policies.levels import rules_level


def _drawn(text: str) -> dict[str, str]:
    """The header's ``Drawn:`` parameters, read back from the comment lines."""
    lines = [line[1:].strip() for line in text.splitlines() if line.startswith("#")]
    body = " ".join(lines).split("Drawn:", 1)[1]
    return dict(part.strip().split(" ", 1) for part in body.split(", "))


def test_the_cli_names_the_registry_families():
    assert tuple(FAMILIES) == FAMILY_NAMES


@pytest.mark.parametrize("family", FAMILY_NAMES)
def test_the_same_seed_gives_the_same_bytes_and_another_seed_another_mission(family):
    assert mission_text(family, 11) == mission_text(family, 11)
    assert mission_text(family, 11) != mission_text(family, 12)


@settings(max_examples=8, deadline=None)
@given(st.sampled_from(FAMILY_NAMES), st.integers(0, 2**40), st.booleans())
def test_a_generated_mission_compiles_passes_check_and_runs(tmp_path_factory, family, seed, odd):
    options = Options(0.5, 0.5) if odd and family != "collaborative" else Options()
    text = mission_text(family, seed, options)
    path = tmp_path_factory.mktemp("g") / "m.epi"
    path.write_text(text)
    assert main(["check", str(path)]) == 0
    mission = parse_mission(text, str(path))
    drawn = _drawn(text)
    # the header says what the file holds
    assert f"generator seed {seed}" in text.splitlines()[0]
    assert len(mission.robots) == int(drawn["robots"])
    assert len(re.findall(r"^robot ", text, re.M)) == int(drawn["robots"])
    if family == "collaborative":
        assert len(mission.goals) == int(drawn["tasks"])
        assert mission.kind.name == "collaborative"
    else:
        assert len(mission.goals) == int(drawn["goals"])
        assert text.count("\nobstacle ") == int(drawn["walls"])
    trial = mission.trial(15, seed % 1000, rules_level(mission.kind))
    assert trial.steps >= 1


def test_generate_writes_numbered_files_and_never_overwrites(tmp_path):
    paths = generate("asymmetry", 3, 40, tmp_path / "a")
    assert [p.name for p in paths] == [f"asymmetry_0000{k}.epi" for k in (40, 41, 42)]
    assert paths[1].read_text() == mission_text("asymmetry", 41)
    with pytest.raises(InvalidArgumentError, match="holds other files"):
        generate("asymmetry", 3, 40, tmp_path / "a")
    assert paths[1].read_text() == mission_text("asymmetry", 41)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["generate", "flocking"], "unknown mission family"),
        (["generate", "rendezvous", "--count", "0"], "count must be"),
        (["generate", "rendezvous", "--seed", "-1"], "seed must be"),
        (["generate", "rendezvous", "--obstacles", "1.5"], "probability"),
        (["generate", "collaborative", "--discs", "0.5"], "no obstacles and no disc"),
    ],
)
def test_bad_input_is_a_clear_error_with_exit_2(tmp_path, capsys, argv, message):
    assert main([*argv, "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert message in err and "hint:" in err and "Traceback" not in err
    assert not (tmp_path / "x").exists()


def test_the_command_writes_into_a_new_folder_then_refuses_it(tmp_path, capsys):
    out = tmp_path / "m"
    assert (
        main(["generate", "collaborative", "--count", "2", "--seed", "5", "--out", str(out)]) == 0
    )
    assert sorted(p.name for p in out.iterdir()) == [
        "collaborative_000005.epi",
        "collaborative_000006.epi",
    ]
    before = (out / "collaborative_000005.epi").read_bytes()
    assert main(["generate", "collaborative", "--out", str(out)]) == 2
    assert (out / "collaborative_000005.epi").read_bytes() == before
