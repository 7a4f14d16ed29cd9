"""Active inference over the set of valid goal configurations.

Imported as ``epistemica.aif``. Depends on ``epistemica.del_`` (errors) only, and on numpy
and scipy. One module per concept:

- :mod:`~epistemica.aif.configurations`: valid configuration sets;
- :mod:`~epistemica.aif.evidence`: range/bearing evidence, sensor dominance, orders 0-3;
- :mod:`~epistemica.aif.likelihood`: per-robot softmax, likelihood over valid rows;
- :mod:`~epistemica.aif.belief`: Bayesian and published belief updates;
- :mod:`~epistemica.aif.information`: entropy, KL divergence, mutual information;
- :mod:`~epistemica.aif.free_energy`: variational and expected free energy, policies;
- :mod:`~epistemica.aif.motion`: candidate controls and predicted poses;
- :mod:`~epistemica.aif.perspective`: the beliefs a robot holds or models, their evidence;
- :mod:`~epistemica.aif.row_index`: sparse gathers over the valid configurations;
- :mod:`~epistemica.aif.one_step`: the one-step expected free energy of candidate positions;
- :mod:`~epistemica.aif.search`: receding-horizon search with pruning of dominated branches;
- :mod:`~epistemica.aif.controller`: the expected-free-energy controller;
- :mod:`~epistemica.aif.task_rollout`: collaborative options valued by rollout over chains
  of fetches (the planner of tasks is :mod:`~epistemica.aif.task_planning`).

See ``docs/aif.md`` for the equations and how they map to the paper.

Examples
--------
>>> from epistemica.aif import valid_configurations, bayes_update
>>> valid_configurations("capacity", 3, 2, capacities=[1, 2]).tolist()
[[0, 1, 1], [1, 0, 1], [1, 1, 0]]
>>> bayes_update([0.5, 0.5], [0.9, 0.1]).round(3).tolist()
[0.9, 0.1]
"""

from epistemica.aif.belief import (
    PUBLISHED_WEIGHT,
    bayes_update,
    bayes_update_log,
    published_update,
    uniform_belief,
)
from epistemica.aif.configurations import (
    FAMILIES,
    count_configurations,
    filter_configurations,
    shared_configurations,
    valid_configurations,
)
from epistemica.aif.controller import Controller, decide
from epistemica.aif.decision import Decision
from epistemica.aif.evidence import (
    BEARING,
    RANGE,
    SENSORS,
    bearing_evidence,
    chain_counts,
    dominates,
    evidence_by_order,
    measurement_stack,
    measurements,
    perspective_sets,
    range_evidence,
)
from epistemica.aif.free_energy import (
    ExpectedFreeEnergy,
    expected_free_energy,
    joint_observation_model,
    joint_preference,
    policy_posterior,
    printed_free_energy,
    published_free_energy,
    select_policy,
    variational_free_energy,
)
from epistemica.aif.information import (
    entropy,
    kl_divergence,
    mutual_information,
    total_correlation,
)
from epistemica.aif.likelihood import (
    configuration_likelihood,
    goal_log_probabilities,
    log_likelihood,
    row_sums,
)
from epistemica.aif.motion import (
    DEFAULT_HEADING_CHANGES,
    DEFAULT_SPEEDS,
    control_grid,
    predict_poses,
)
from epistemica.aif.one_step import Terms
from epistemica.aif.perspective import Perspective
from epistemica.aif.task_rollout import rollout_values

__all__ = [
    "BEARING",
    "DEFAULT_HEADING_CHANGES",
    "DEFAULT_SPEEDS",
    "FAMILIES",
    "PUBLISHED_WEIGHT",
    "RANGE",
    "SENSORS",
    "Controller",
    "Decision",
    "ExpectedFreeEnergy",
    "Perspective",
    "Terms",
    "bayes_update",
    "bayes_update_log",
    "bearing_evidence",
    "chain_counts",
    "configuration_likelihood",
    "control_grid",
    "count_configurations",
    "decide",
    "dominates",
    "entropy",
    "evidence_by_order",
    "expected_free_energy",
    "filter_configurations",
    "goal_log_probabilities",
    "joint_observation_model",
    "joint_preference",
    "kl_divergence",
    "log_likelihood",
    "measurement_stack",
    "measurements",
    "mutual_information",
    "perspective_sets",
    "policy_posterior",
    "predict_poses",
    "printed_free_energy",
    "published_free_energy",
    "published_update",
    "range_evidence",
    "rollout_values",
    "row_sums",
    "select_policy",
    "shared_configurations",
    "total_correlation",
    "uniform_belief",
    "valid_configurations",
    "variational_free_energy",
]
