"""Kinematic multi-robot simulation: missions, reasoning levels, baselines.

Imported as ``epistemica.sim``. Depends on ``epistemica.aif`` and ``epistemica.del_``,
never on the package root. One module per concept:

- :mod:`~epistemica.sim.scenario`: :class:`Scenario`, the world and its rules;
- :mod:`~epistemica.sim.sensing`: observation models and what each robot knows;
- :mod:`~epistemica.sim.missions`: when a mission holds;
- :mod:`~epistemica.sim.policy`: the policy interface;
- :mod:`~epistemica.sim.baselines`: greedy (``"zero"``) and the convention;
- :mod:`~epistemica.sim.active`: the active-inference levels, with their parts
  :mod:`~epistemica.sim.configuration_sets`, :mod:`~epistemica.sim.search` and their
  parameters :mod:`~epistemica.sim.parameters`;
- :mod:`~epistemica.sim.levels`: the table of level names;
- :mod:`~epistemica.sim.events`: observation events (triggers, effects, observers);
- :mod:`~epistemica.sim.worlds`: configurations as worlds of the logic;
- :mod:`~epistemica.sim.tasking`: multitask upper level (which tasks now);
- :mod:`~epistemica.sim.simulate`: :func:`simulate`, one trial;
- :mod:`~epistemica.sim.trial`: :class:`Trial`, its record.

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> trial = simulate(Scenario.paper("allocation", 3, seed=0), "convention", seed=0)
>>> trial.success, trial.trajectory.shape[1:]
(True, (3, 3))
"""

from epistemica.sim.active import ActiveInference
from epistemica.sim.baselines import Convention, Greedy
from epistemica.sim.levels import LEVELS, REASONING, make_policy
from epistemica.sim.missions import mission_holds
from epistemica.sim.parameters import ActiveParameters
from epistemica.sim.policy import Decisions, FunctionPolicy, Policy, steer
from epistemica.sim.scenario import MISSIONS, OBSERVATIONS, Scenario
from epistemica.sim.sensing import Observations, Sensing
from epistemica.sim.simulate import simulate
from epistemica.sim.trial import Trial

__all__ = [
    "LEVELS",
    "MISSIONS",
    "OBSERVATIONS",
    "REASONING",
    "ActiveInference",
    "ActiveParameters",
    "Convention",
    "Decisions",
    "FunctionPolicy",
    "Greedy",
    "Observations",
    "Policy",
    "Scenario",
    "Sensing",
    "Trial",
    "make_policy",
    "mission_holds",
    "simulate",
    "steer",
]
