"""The part every goal-mission family draws: workspace, robots, goals, obstacles, sensing.

Examples
--------
>>> from epistemica.generate.common import Draw
>>> d = Draw()
>>> team = draw_team(d, np.random.default_rng(1), robots=3, goals=4)
>>> len(team.goals), d.lines[0].startswith("workspace")
(4, True)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from epistemica.generate.common import (
    Draw,
    draw_obstacles,
    draw_points,
    number,
    obstacle_line,
    point,
    sensor_names,
)

__all__ = ["PLAIN", "Options", "Team", "draw_team", "goal_mission", "sensing_line"]


class Options(NamedTuple):
    """The family options: the probability that a mission has obstacles, disc robots."""

    obstacles: float = 0.0
    discs: float = 0.0


#: No obstacles, no disc robots.
PLAIN = Options()


class Team(NamedTuple):
    """What a family needs of the drawn team to write the rest of the mission."""

    workspace: float
    robots: list[str]
    goals: list[str]
    sensing_range: float


def sensing_line(rng: np.random.Generator, workspace: float, draw: Draw) -> float:
    """Draw the ``sensing`` line: model, noise, range (or none), discovery; its range."""
    model = ("paper", "honest")[int(rng.integers(0, 2))]
    noise = round(float(rng.uniform(0.1, 2.0)), 1)
    sight = round(float(rng.uniform(6.0, workspace)), 0) if rng.random() < 0.7 else 0.0
    discovery = round(float(rng.uniform(3.0, 8.0)), 0)
    line = f"sensing model {model} noise {number(noise)} discovery {number(discovery)}"
    if sight:
        line += f" range {number(sight)}"
    draw.add(line)
    draw.note(model=model, noise=noise, sight=int(sight) or "everywhere", discovery=int(discovery))
    return sight or np.inf


def draw_team(
    draw: Draw,
    rng: np.random.Generator,
    robots: int,
    goals: int,
    options: Options = PLAIN,
    closed: frozenset[int] = frozenset(),
) -> Team:
    """Workspace 20-40 m, ``robots`` robots with random sensors at random places, ``goals``
    goals (those in ``closed`` written ``closed``), maybe 1-3 walls (probability
    ``options.obstacles``) and disc robots of radius 0.2-0.5 m (``options.discs``)."""
    workspace = float(rng.integers(20, 41))
    walls = (
        draw_obstacles(rng, workspace, int(rng.integers(1, 4)))
        if (rng.random() < options.obstacles)
        else []
    )
    radius = round(float(rng.uniform(0.2, 0.5)), 1) if rng.random() < options.discs else 0.0
    starts = draw_points(rng, robots, workspace, walls, gap=2 * radius + 0.5)
    places = draw_points(rng, goals, workspace, walls, gap=2.0)
    sensors = sensor_names(rng, robots)
    draw.note(workspace=int(workspace), robots=robots, goals=goals, walls=len(walls))
    draw.note(disc_radius=radius or "none")
    draw.add(f"workspace {int(workspace)}")
    names = [f"r{i + 1}" for i in range(robots)]
    disc = f" radius {number(radius)}" if radius else ""
    for name, sensor, xy in zip(names, sensors, starts, strict=True):
        draw.add(f"robot {name}: {sensor} at {point(xy)}{disc}")
    gnames = [f"g{j + 1}" for j in range(goals)]
    for j, (name, xy) in enumerate(zip(gnames, places, strict=True)):
        draw.add(f"goal {name} at {point(xy)}" + (" closed" if j in closed else ""))
    draw.add(*(obstacle_line(w) for w in walls))
    sight = sensing_line(rng, workspace, draw)
    return Team(workspace, names, gnames, sight)


#: The study line of every goal family (the benchmark passes its own levels and seeds).
STUDY = "simulate trials 2 seed 0 steps 100 levels convention, first, third_shared, third"


def goal_mission(
    kind: str, rng: np.random.Generator, robots: int, goals: int, options: Options
) -> Draw:
    """A ``kind`` mission of the team draw, whose settles are seen by the robots near them
    (probability 0.7) or by every robot, and its study line."""
    d = Draw()
    d.add(f"mission {kind}")
    draw_team(d, rng, robots, goals, options)
    seen = ("nearby", "everyone")[int(rng.random() < 0.3)]
    d.note(settle_seen_by=seen)
    d.add(f"event settle seen by {seen}", STUDY)
    return d
