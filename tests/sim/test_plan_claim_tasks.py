"""On task missions every later teammate yields a claimed task (``PlanningStage``,
``scenario.kind.tasks``): the task closes on its first arrival and every robot's upper level
re-assigns the team, so none comes to it anyway, whatever its type (aif.md §6g, session 53).
"""

import numpy as np

from epistemica.aif.planning import Planner
from epistemica.aif.teammates import TYPES
from epistemica.sim import Scenario
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage

GOALS = [[0.0, 0.0], [10.0, 0.0]]
SWAP = [[0, 1], [1, 0]]  # two robots, two tasks (or goals), one each
AT = [[2.0, 0.0], [4.0, 0.0]]  # robot 0 2 m from goal 0, robot 1 4 m from it
# Robot 1 at order 0: the uniform prior times exp(-d / 5), pi_1 = (0.5987, 0.4013).
PI1 = np.exp([-0.8, -1.2]) / np.exp([-0.8, -1.2]).sum()
FAR = 0.8 - np.log(PI1[0])  # goal 1: robot 1 is there first (6 s against 8 s), unclaimed


def plan(mission: str):
    """Robot 0's plan with the stage's options and claim (the default ``plan_claim`` 6) on
    the worked scene: unit speeds, tau = 10 s (temperature 1, goals 10 m apart), eta = 5 m
    (evidence 0.5). Robot 1 was read as team with 1/8 (types 1, 4, 1, 2), every ad hoc
    type of it on goal 0."""
    stage = PlanningStage(Scenario.paper(mission, 2, 2, seed=0), ActiveParameters(), order=1)
    probs = np.zeros((2, len(TYPES), 2))
    probs[:, :, 0] = 1.0
    stage._types[0] = np.log([[0.5, 1 / 6, 1 / 6, 1 / 6], [1.0, 4.0, 1.0, 2.0]])
    stage._typing[0] = (0, np.arange(2), np.zeros((2, 2)), np.ones(2, bool), probs)
    stage._last[0] = (0, np.zeros((2, 2)), np.zeros(2, int))  # both seen
    options = {**stage.options, "temperature": 1.0, "evidence": 0.5}
    planner = Planner(GOALS, SWAP, [1.0, 1.0], order=1, **options)
    return stage, planner.plan(0, AT, yields=stage.yields(0))


def test_a_task_is_yielded_by_every_later_teammate_whatever_its_type():
    # Allocation: robot 1, later at goal 0, yields with 1/8; if not, it comes by its ad hoc
    # types to goal 0, so goal 0 forms only if it yields: G(0) = max(2, 6) / 10 - ln(1/8)
    # = 2.679 against G(1) = 0.8 - ln pi_1(0) = 1.313: the robot leaves its near goal.
    stage, goal_plan = plan("allocation")
    np.testing.assert_allclose(goal_plan.G, [0.6 + np.log(8.0), FAR])
    assert goal_plan.goal == 1 and stage.keeping
    # Tasks: robot 0 does task 0 first, it closes and robot 1 is re-assigned: it yields
    # for sure, G(0) = 0.6, and the robot takes the task it reaches first.
    stage, task_plan = plan("multitask")
    np.testing.assert_allclose(task_plan.G, [0.6, FAR])
    assert task_plan.goal == 0
    assert stage.yields(0) is None and not (stage.by_type or stage.yielding or stage.driving)
