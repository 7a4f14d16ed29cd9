"""Gymnasium ids for every mission family: ``import epistemica.envs``, then
``gymnasium.make("epistemica/Nested-PrivateGoal-3-v0")``.

Importing this module registers (again: replaced) one id per

- **published protocol family** (:mod:`epistemica.sim.engine.env_registry`, registered by
  importing :mod:`epistemica.sim.engine.env`): ``epistemica/Rendezvous-v0``,
  ``Allocation-v0``, ``Multitask-v0``;
- **shipped mission file** of the repository's ``specs/`` folder (the nested missions,
  the events, the stress suite, the collaborative missions, ...), named from its path
  (:func:`env_id`): ``nested/private_goal_3.epi`` -> ``epistemica/Nested-PrivateGoal-3-v0``,
  ``capacity.epi`` -> ``epistemica/Specs-Capacity-v0``. ``specs/`` is in a source
  checkout, not in the wheel: elsewhere :func:`register` takes the folder;
- **generated family** (:mod:`epistemica.generate`): ``epistemica/Generated-Rendezvous-v0``,
  ``Generated-Allocation-v0``, ``Generated-Asymmetry-v0``, ``Generated-Collaborative-v0``:
  the mission drawn from generator seed ``generator_seed`` (a keyword of
  ``gymnasium.make``, default 0; a mission's team, goals and workspace fix the spaces, so
  one environment holds one mission, and another generator seed is another environment).

Each id makes a :class:`~epistemica.sim.engine.env.RobotEnv` of the mission's first robot
among teammates of a reasoning level (``teammates=``, default the rules' level the
learned policy was measured with: ``"rules-third"``, ``"rules"`` on a collaborative
mission) with actions in ``[-1, 1]²`` (``normalized=True``); each reset draws trial
``seed`` (a mission file's layout where it is drawn at random, the noise) and every keyword
of ``RobotEnv`` passes through ``gymnasium.make``. A mission file's ``policy`` line is the
teammates' parameters.

Examples
--------
>>> env_id("specs/nested/private_goal_3.epi", "specs")
'epistemica/Nested-PrivateGoal-3-v0'
>>> env_id("specs/capacity.epi", "specs")
'epistemica/Specs-Capacity-v0'
>>> import gymnasium
>>> env = gymnasium.make("epistemica/Generated-Asymmetry-v0", generator_seed=3)
>>> observation, info = env.reset(seed=0)
>>> env.unwrapped.multi.scenario.n_robots, env.unwrapped.agent
(4, 'r1')
"""

from __future__ import annotations

import re
from pathlib import Path

import gymnasium  # the env extra: pip install "epistemica[env]"

from epistemica.generate import FAMILIES, Options, mission_text
from epistemica.input_files import file_kind
from epistemica.mission import Mission, load_mission, parse_mission
from epistemica.sim.engine.env import RobotEnv
from epistemica.sim.engine.env_registry import register as register_paper_families

__all__ = [
    "GENERATED",
    "IDS",
    "SPECS",
    "env_id",
    "generated_env",
    "mission_env",
    "mission_files",
    "register",
]

#: The repository's ``specs/`` folder (present in a source checkout).
SPECS = Path(__file__).resolve().parents[2] / "specs"
#: The generated families that have ids (every one).
GENERATED = tuple(FAMILIES)


def _camel(name: str) -> str:
    """``private_goal_3`` -> ``PrivateGoal-3``: words capitalised, a number after a dash (so
    that ``noise64_2`` is ``Noise64-2``)."""
    out = ""
    for part in re.split(r"[_\W]+", name):
        out += f"-{part}" if part.isdigit() and out else part[:1].upper() + part[1:]
    return out


def env_id(path: str | Path, specs: str | Path) -> str:
    """The Gymnasium id of mission file ``path`` of the folder ``specs``: its folder (or
    ``Specs`` at the top) and its name in CamelCase."""
    relative = Path(path).relative_to(specs)
    folder = _camel(relative.parent.as_posix()) if relative.parent.parts else "Specs"
    return f"epistemica/{folder}-{_camel(relative.stem)}-v0"


def mission_files(specs: str | Path = SPECS) -> list[Path]:
    """The mission files under ``specs`` (spec files left out), sorted; none when the
    folder is absent."""
    paths = sorted(Path(specs).rglob("*.epi"))
    return [p for p in paths if file_kind(p.read_text(encoding="utf-8"))[0] == "mission"]


def _robot_env(
    mission: Mission, robot: str | int, teammates: str | None, options: dict
) -> RobotEnv:
    options.setdefault("parameters", mission.parameters)
    options.setdefault("normalized", True)
    return RobotEnv(mission, robot, teammates, **options)


def mission_env(
    path: str | Path, robot: str | int = 0, teammates: str | None = None, **options
) -> RobotEnv:
    """The :class:`~epistemica.sim.engine.env.RobotEnv` of mission file ``path`` (what a
    shipped mission's id makes)."""
    return _robot_env(load_mission(path), robot, teammates, options)


def generated_env(
    family: str,
    generator_seed: int = 0,
    robot: str | int = 0,
    teammates: str | None = None,
    generator_options: Options | None = None,
    **options,
) -> RobotEnv:
    """The :class:`~epistemica.sim.engine.env.RobotEnv` of the mission ``family`` draws from
    ``generator_seed`` (what a generated family's id makes)."""
    text = mission_text(family, generator_seed, generator_options or Options())
    mission = parse_mission(text, f"<generated {family} {generator_seed}>")
    return _robot_env(mission, robot, teammates, options)


def _register(name: str, entry_point, kwargs: dict) -> None:
    if name in gymnasium.registry:
        del gymnasium.registry[name]
    gymnasium.register(id=name, entry_point=entry_point, kwargs=kwargs, disable_env_checker=True)


def register(specs: str | Path | None = SPECS) -> list[str]:
    """Register every family's id (the published protocol's, one per mission file under
    ``specs``, the generated families'); returns the ids."""
    ids = register_paper_families()
    for path in mission_files(specs) if specs is not None else []:
        ids.append(env_id(path, specs))
        _register(ids[-1], mission_env, {"path": str(path)})
    for family in GENERATED:
        ids.append(f"epistemica/Generated-{_camel(family)}-v0")
        _register(ids[-1], generated_env, {"family": family})
    return ids


#: Every id this import registered.
IDS = register()
