"""Kinematic multi-robot simulation: missions, reasoning levels, baselines, studies.

Imported as ``epistemica.sim``. Depends on ``epistemica.aif`` and ``epistemica.del_``,
never on the package root. Four subpackages, by concern:

- :mod:`~epistemica.sim.engine`: the world of a trial (:class:`Scenario`), perception,
  events and the team's knowledge, and the one loop (:func:`simulate`, :class:`Trial`);
- :mod:`~epistemica.sim.kinds`: the kinds of mission (:data:`KINDS`), one object each;
- :mod:`~epistemica.sim.policies`: the policy interface, the baselines, the
  active-inference levels and their parts, and the one level registry (:data:`LEVELS`);
- :mod:`~epistemica.sim.study`: sweeps, the results file, reports, traces and figures.

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> trial = simulate(Scenario.paper("allocation", 3, seed=0), "convention", seed=0)
>>> trial.success, trial.trajectory.shape[1:]
(True, (3, 3))
"""

from epistemica.sim.engine.scenario import OBSERVATIONS, Scenario
from epistemica.sim.engine.sensing import Observations, Sensing
from epistemica.sim.engine.simulate import simulate
from epistemica.sim.engine.trial import Trial
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.registry import KINDS, kind_named, mission_holds
from epistemica.sim.policies.active import ActiveInference
from epistemica.sim.policies.baselines import Convention, Greedy
from epistemica.sim.policies.levels import LEVELS, REASONING, make_policy
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.policy import Decisions, FunctionPolicy, Policy, steer

__all__ = [
    "KINDS",
    "LEVELS",
    "OBSERVATIONS",
    "REASONING",
    "ActiveInference",
    "ActiveParameters",
    "Convention",
    "Decisions",
    "FunctionPolicy",
    "Greedy",
    "MissionKind",
    "Observations",
    "Policy",
    "Scenario",
    "Sensing",
    "Trial",
    "kind_named",
    "make_policy",
    "mission_holds",
    "simulate",
    "steer",
]
