"""Gymnasium ids for every mission family (``epistemica.envs``): every shipped mission file
(the nested and the collaborative ones included) and every generated family; each id makes
the mission it names, resets and steps, and ``check_env`` passes without a warning on a
representative few."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")  # in the test extra: skipped only without it
pytest.importorskip("pettingzoo")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from epistemica.del_.errors import InvalidArgumentError  # noqa: E402
from epistemica.envs import env_id, mission_files, register  # noqa: E402
from epistemica.generate import mission_text  # noqa: E402
from epistemica.mission import load_mission, parse_mission  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SPECS = ROOT / "specs"
# The repository's files, wherever the package is installed (an installed wheel has no
# specs/ folder of its own: its import registers the published and generated ids only).
IDS = register(SPECS)


def _missions() -> dict[Path, str]:
    """Every mission file under specs/ -> its kind (by compiling it: the language's own
    answer, not the registry's reading of the first statement)."""
    out = {}
    for path in sorted(SPECS.rglob("*.epi")):
        first = next(
            line for line in path.read_text().splitlines() if line.strip() and line[0] != "#"
        )
        if first.split()[0] == "mission":
            out[path] = load_mission(path).kind.name
    return out


MISSIONS = _missions()
FILE_IDS = {env_id(path, SPECS): path for path in MISSIONS}


def _places(scenario) -> np.ndarray:
    """The goals, or a collaborative mission's tasks."""
    return scenario.goals if hasattr(scenario, "goals") else scenario.tasks


def test_every_shipped_mission_has_an_id_and_no_other_file_does():
    assert len(IDS) == len(set(IDS))  # no two files share an id
    assert mission_files(SPECS) == sorted(FILE_IDS.values())
    assert set(FILE_IDS) <= set(IDS)
    nested = sorted((SPECS / "nested").glob("*.epi"))
    assert len(nested) == 10 and all(env_id(p, SPECS) in IDS for p in nested)
    assert "epistemica/Nested-PrivateGoal-3-v0" in IDS
    assert "epistemica/Stress-AllocationNoise64-2-v0" in IDS  # the size stays apart
    assert "epistemica/Collaborative-Tasks-5-v0" in IDS
    assert set(MISSIONS.values()) >= {"rendezvous", "allocation", "multitask", "collaborative"}
    generated = [i for i in IDS if i.startswith("epistemica/Generated-")]
    families = ("Rendezvous", "Allocation", "Asymmetry", "Collaborative")
    assert generated == [f"epistemica/Generated-{f}-v0" for f in families]
    paper = ["epistemica/Rendezvous-v0", "epistemica/Allocation-v0", "epistemica/Multitask-v0"]
    assert set(IDS) == set(paper) | set(FILE_IDS) | set(generated)


@pytest.mark.parametrize("name", sorted(FILE_IDS), ids=lambda n: n.split("/")[1])
def test_each_file_id_makes_its_mission_resets_and_steps(name):
    env = gymnasium.make(name)
    observation, _ = env.reset(seed=3)
    expected = load_mission(FILE_IDS[name]).scenario(3)
    made = env.unwrapped.multi.scenario
    assert np.array_equal(made.starts, expected.starts)
    assert np.array_equal(_places(made), _places(expected))
    assert env.observation_space.contains(observation)
    observation, reward, _, truncated, _ = env.step(env.action_space.sample())
    assert env.observation_space.contains(observation) and np.isfinite(reward)
    assert env.unwrapped.multi.step_count == 1 and not truncated


@pytest.mark.parametrize("family", ["rendezvous", "allocation", "asymmetry", "collaborative"])
def test_each_generated_id_makes_the_mission_of_its_generator_seed(family):
    name = f"epistemica/Generated-{family.capitalize()}-v0"
    for seed in (0, 7):
        env = gymnasium.make(name, generator_seed=seed)
        env.reset(seed=1)
        expected = parse_mission(mission_text(family, seed)).scenario(1)
        assert np.array_equal(_places(env.unwrapped.multi.scenario), _places(expected))
        assert np.array_equal(env.unwrapped.multi.scenario.starts, expected.starts)
        env.step(env.action_space.sample())


@pytest.mark.parametrize(
    ("name", "options"),
    [
        ("epistemica/Nested-PrivateGoal-3-v0", {"epistemic": True}),
        ("epistemica/Events-DoorCloses-v0", {}),
        ("epistemica/Specs-MultiTask-v0", {"teammates": "convention"}),
        ("epistemica/Stress-RendezvousHardest-5-v0", {}),
        ("epistemica/Generated-Asymmetry-v0", {"generator_seed": 3}),
        ("epistemica/Generated-Allocation-v0", {"generator_seed": 11}),
        ("epistemica/Collaborative-Tasks-3-v0", {"epistemic": True}),
        ("epistemica/Generated-Collaborative-v0", {"generator_seed": 2}),
    ],
    ids=lambda v: v.split("/")[1] if isinstance(v, str) else "",
)
def test_check_env_passes_without_a_warning_on_a_representative_few(name, options):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning fails
        env = gymnasium.make(name, **options)
        check_env(env.unwrapped, skip_render_check=True)


def test_the_ids_pass_the_missions_policy_and_take_the_environments_keywords():
    path = SPECS / "nested" / "private_goal_3.epi"
    env = gymnasium.make(env_id(path, SPECS), robot="r2", teammates="zero", shaping=0.0)
    assert env.unwrapped.agent == "r2" and env.unwrapped.multi.shaping == 0.0
    assert env.unwrapped.multi.parameters == load_mission(path).parameters
    with pytest.raises(InvalidArgumentError, match="unknown keyword"):
        gymnasium.make(env_id(path, SPECS), colour="red")


def test_register_reads_the_folder_it_is_given(tmp_path):
    (tmp_path / "team").mkdir()
    (tmp_path / "team" / "two_of_us.epi").write_text(
        "mission rendezvous\nworkspace 30\nrobot r1..r2: random at random\n"
        "goal g1..g2 at random\nsensing noise 0.5 model paper\n"
    )
    (tmp_path / "puzzle.epi").write_text((SPECS / "puzzles" / "coin_toss.epi").read_text())
    try:
        ids = register(tmp_path)
        assert "epistemica/Team-TwoOfUs-v0" in ids
        assert not any("Puzzle" in i for i in ids)  # a spec, not a mission
        assert gymnasium.make("epistemica/Team-TwoOfUs-v0").unwrapped.multi.scenario.n_robots == 2
    finally:
        register(SPECS)  # the shipped ids again
        del gymnasium.registry["epistemica/Team-TwoOfUs-v0"]
