"""A collaborative mission file's world and parameters (``mission collaborative``).

Its tasks say how many robots they need (``task t1 at random needs 3``); what is placed
``at random`` is drawn from the trial seed (:func:`epistemica.sim.engine.draws.draw_layout`), as
in every mission; ``policy NAME VALUE`` lines set
:class:`~epistemica.sim.policies.collaborative_levels.CollaborativeParameters`.
"""

from __future__ import annotations

from typing import Any

from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.sim.engine.draws import draw_layout
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.policies.collaborative_parameters import CollaborativeParameters

__all__ = ["collaborative_parameters", "collaborative_scenario"]


def collaborative_scenario(mission: Any, seed: int) -> CollaborativeScenario:
    """The :class:`~epistemica.sim.kinds.collaborative.CollaborativeScenario` of trial ``seed``."""
    p, n, m = mission.parts, len(mission.robots), len(mission.goals)
    options = p.options
    workspace = options.get("workspace", 40.0)
    layout = draw_layout(seed, n, m, workspace=workspace)
    tasks = [t.place or layout.goals[j].tolist() for j, t in enumerate(p.goals)]
    starts = []
    for i, robot in enumerate(p.robots):
        pose = list(robot.place) if robot.place else layout.starts[i].tolist()
        starts.append(pose + [0.0] * (3 - len(pose)))
    try:
        return CollaborativeScenario(
            starts,
            tasks,
            p.capacities,
            workspace=workspace,
            sensing_range=options.get("sensing_range", 8.0),
            completion_radius=options.get("success_radius", 1.5),
            max_steps=options.get("max_steps", 400),
            max_speed=[r.speed for r in p.robots],
            max_turn=[r.turn for r in p.robots],
            process_noise=options.get("process_noise", 0.0),
            events=p.events,
            robot_names=mission.robots,
            task_names=mission.goals,
            sensors=tuple(r.sensor for r in p.robots),
        )
    except InvalidArgumentError as exc:
        raise _located(mission, exc, None) from None


def collaborative_parameters(mission: Any, value: Any) -> CollaborativeParameters:
    """The parameters after the file's ``policy`` lines (``value`` reads one word)."""
    out = CollaborativeParameters()
    for name, text, token in mission.parts.policy:
        try:
            out = out.replace(**{name: value(text)})
        except (InvalidArgumentError, TypeError, ValueError) as exc:
            raise _located(mission, exc, token) from None
    return out


def _located(mission: Any, exc: Exception, token) -> SpecError:
    return SpecError(
        getattr(exc, "message", str(exc)),
        line=1 if token is None else token.line,
        column=1 if token is None else token.column,
        source=mission.source,
        filename=mission.filename,
        hint=getattr(exc, "hint", None) or "see docs/language.md, 'Collaborative tasks'",
    )
