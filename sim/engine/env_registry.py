"""Gymnasium ids for the published protocol's families: ``epistemica/Rendezvous-v0``, ...
(the ids of the mission files and the generated families are the package root's,
:mod:`epistemica.envs`, which reads mission files; importing it registers these too).

A family draws one trial's layout per seed (:class:`PaperFamily`, the published protocol's
generator, :meth:`epistemica.sim.Scenario.paper`); each id makes a
:class:`~epistemica.sim.engine.env.RobotEnv` of its first robot among teammates of a reasoning
level (``teammates=``, default ``"rules-third"``, the rules' one-step controller), with
actions normalised to ``[-1, 1]²`` (``normalized=True``; every keyword of ``RobotEnv``
passes through ``gymnasium.make``). :func:`register` runs when
:mod:`epistemica.sim.engine.env` is imported (Gymnasium loads no plugins by itself:
import it first, or name it in the id,
``gymnasium.make("epistemica.sim.engine.env:epistemica/Rendezvous-v0")``).

==========================  ================================================================
``epistemica/Rendezvous-v0``  3 robots, 3 goals: meet at one goal
``epistemica/Allocation-v0``  3 robots, 3 goals: one robot per goal
``epistemica/Multitask-v0``   3 robots, 5 tasks: visit every task
==========================  ================================================================

Examples
--------
>>> PaperFamily("rendezvous", 3, 3).scenario(2).n_robots
3
>>> sorted(FAMILIES)
['Allocation', 'Multitask', 'Rendezvous']
"""

from __future__ import annotations

from epistemica.sim.engine.scenario import Scenario

__all__ = ["FAMILIES", "PaperFamily", "register"]


class PaperFamily:
    """A mission family: the published protocol's trial ``seed`` for a team size (an
    object with ``scenario(seed)``, as :class:`~epistemica.sim.engine.env.MissionEnv` takes)."""

    def __init__(self, mission: str, robots: int, goals: int, **options) -> None:
        self.mission, self.robots, self.goals, self.options = mission, robots, goals, options

    def scenario(self, seed: int) -> Scenario:
        """The layout of trial ``seed``."""
        return Scenario.paper(self.mission, self.robots, self.goals, seed=seed, **self.options)

    def __repr__(self) -> str:
        return f"PaperFamily({self.mission!r}, {self.robots}, {self.goals})"


#: Id stem -> (mission, robots, goals).
FAMILIES = {
    "Rendezvous": ("rendezvous", 3, 3),
    "Allocation": ("allocation", 3, 3),
    "Multitask": ("multitask", 3, 5),
}


def register() -> list[str]:
    """Register every family's id with Gymnasium (again: replaced); returns the ids."""
    import gymnasium  # optional: the env extra

    ids = []
    for stem, (mission, robots, goals) in FAMILIES.items():
        env_id = f"epistemica/{stem}-v0"
        if env_id in gymnasium.registry:
            del gymnasium.registry[env_id]
        gymnasium.register(
            id=env_id,
            entry_point="epistemica.sim.engine.env:RobotEnv",
            kwargs={"source": PaperFamily(mission, robots, goals), "normalized": True},
            disable_env_checker=True,
        )
        ids.append(env_id)
    return ids
