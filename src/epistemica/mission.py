"""Mission files: a multi-robot mission written in the epistemic language.

A mission file (``.epi``, grammar ``mission.lark``) declares robots, goals or tasks, which
goal configurations are valid, what each robot senses and knows at the start, the
observation events that update what robots know, epistemic claims, and its Monte Carlo
study. :func:`load_mission` compiles it into a :class:`Mission`: the Kripke model over the
valid configurations, the simulator's :class:`~epistemica.sim.Scenario`, the events as
action models, and the claims. ``docs/language.md`` ("Mission files") is the reference.

Examples
--------
>>> m = parse_mission('''
... mission allocation
... robot r1: range at (5, 5)
... robot r2: bearing at (25, 5)
... goal g1 at (5, 20)
... goal g2 at (25, 20)
... learns r1: assigned(r1, g1)
... check "r1 knows where r2 goes": K[r1] assigned(r2, g2)
... check "r2 does not": K[r2] assigned(r2, g2) expect false
... ''')
>>> len(m.configurations()), [m.holds(c.formula) == c.expected for c in m.checks]
(2, [True, True])
>>> m.scenario().mission, m.scenario().sensors
('allocation', ('range', 'bearing'))
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from epistemica._mission_compiler import compile_text
from epistemica.aif.configurations import count_configurations, valid_configurations
from epistemica.del_ import ActionModel, Check, Formula, KripkeModel, parse_formula
from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.del_.planning.configuration_model import (
    MAX_CONFIGURATIONS,
    configuration_model,
    observed,
)
from epistemica.input_files import read_input
from epistemica.sim._streams import trial_streams
from epistemica.sim.knowledge import rows_satisfying
from epistemica.sim.scenario import Scenario
from epistemica.sim.simulate import REASONING

__all__ = ["Mission", "Study", "load_mission", "parse_mission"]

#: Configurations beyond which a mission's valid set is not enumerated at compile time.
ENUMERATION_LIMIT = 200_000


@dataclass(frozen=True)
class Study:
    """The Monte Carlo comparison a mission file asks for (its ``simulate`` line).

    Attributes
    ----------
    trials : int
        Trials per reasoning level (default 20).
    seed : int
        Seed of the first trial; trial ``t`` uses ``seed + t``.
    levels : tuple of str
        Reasoning levels to compare (default ``zero, convention, first, third``).
    """

    trials: int = 20
    seed: int = 0
    levels: tuple[str, ...] = ("zero", "convention", "first", "third")


@dataclass(frozen=True, eq=False)
class Mission:
    """A compiled mission file.

    Attributes
    ----------
    name : str
        The file's stem.
    kind : str
        ``"rendezvous"``, ``"allocation"``, ``"capacity"`` or ``"multitask"``.
    robots, goals : tuple of str
        Names, in declaration order (goals are the tasks of a multitask mission).
    checks : tuple of Check
        The epistemic claims (``check`` lines).
    study : Study
    filename, source : str
    """

    name: str
    kind: str
    robots: tuple[str, ...]
    goals: tuple[str, ...]
    checks: tuple[Check, ...]
    study: Study
    filename: str
    source: str = field(repr=False)
    parts: dict[str, Any] = field(repr=False)

    # -- the simulator's view ----------------------------------------------------------

    def scenario(self, seed: int | None = None) -> Scenario:
        """The :class:`~epistemica.sim.Scenario` of trial ``seed`` (default the study's
        first seed): robots and goals placed ``at random`` are drawn from the seed's
        geometry stream (starts uniform in the workspace, goals in it less 1 m borders),
        the rest as written.
        """
        seed = self.study.seed if seed is None else seed
        p, n, m = self.parts, len(self.robots), len(self.goals)
        options = dict(p["options"])
        workspace = options.get("workspace", 30.0)
        geometry = trial_streams(int(seed), n).geometry
        goal_xy = geometry.uniform(1.0, workspace - 1.0, size=(m, 2))
        start_xy = geometry.uniform(0.0, workspace, size=(n, 2))
        goals = [
            spec["place"][0] if spec["place"] else goal_xy[g].tolist()
            for g, spec in enumerate(p["goal_specs"].values())
        ]
        starts = []
        for i, spec in enumerate(p["robot_specs"].values()):
            place = spec["place"]
            pose = list(place[0]) if place else start_xy[i].tolist()
            starts.append(pose + [0.0] * (3 - len(pose)))
        known = p["known_goals"]
        if isinstance(known, str):  # "random": per goal, a non-empty subset of the robots
            known = _random_knowledge(_mission_streams(int(seed), n)[0], n, m)
        speeds = [spec.get("speed", 1.0) for spec in p["robot_specs"].values()]
        turns = [spec.get("turn", np.pi) for spec in p["robot_specs"].values()]
        drawn = trial_streams(int(seed), n).sensors.integers(0, 2, size=n)  # as Scenario.paper
        sensors = [
            ("range", "bearing")[drawn[i]] if spec["sensor"] == "random" else spec["sensor"]
            for i, spec in enumerate(p["robot_specs"].values())
        ]
        try:
            return Scenario(
                self.kind,
                starts,
                goals,
                sensors,
                capacities=p["capacities"],
                known_goals=known,
                max_speed=speeds,
                max_turn=turns,
                valid=self._table,
                events=p["events"],
                told=tuple(
                    (tuple(r in names for r in self.robots), fact) for names, fact in p["learns"]
                ),
                robot_names=self.robots,
                goal_names=self.goals,
                **options,
            )
        except InvalidArgumentError as exc:
            raise self._located(exc) from None

    def policies(self, seed: int | None = None) -> dict[int, str]:
        """The ad hoc teammate of trial ``seed`` (its ``teammate`` line): robot index to
        level; ``teammate random`` draws the robot from the seed's mission stream."""
        seed = self.study.seed if seed is None else seed
        out = {}
        for robot, level, _ in self.parts["teammates"]:
            if robot == "random":
                stream = _mission_streams(int(seed), len(self.robots))[1]
                out[int(stream.integers(len(self.robots)))] = level
            else:
                out[self.robots.index(robot)] = level
        return out

    def _located(self, exc: InvalidArgumentError) -> SpecError:
        """A scenario error, located at the robot or setting it names when possible."""
        line, column = 1, 1
        specs = self.parts["robot_specs"]
        for index, spec in enumerate(specs.values()):
            if f"robot {index} " in exc.message:
                line, column = spec["token"].line, spec["token"].column
        return SpecError(
            exc.message,
            line=line,
            column=column,
            source=self.source,
            filename=self.filename,
            hint=exc.hint,
        )

    @functools.cached_property
    def _table(self) -> np.ndarray | None:
        """The valid configurations after ``valid`` and ``initially`` (None: the whole
        set of the mission kind, unconstrained, or a multitask mission)."""
        p = self.parts
        if self.kind == "multitask":
            return None
        n, m = len(self.robots), len(self.goals)
        constraints = p["valid"] + p["initially"]
        total = count_configurations(self.kind, n, m, p["capacities"])
        if total == 0:
            raise self._empty("the mission kind allows no configuration of these robots")
        if not constraints:
            return None
        if total > ENUMERATION_LIMIT:
            raise SpecError(
                f"{total} configurations are too many to constrain with 'valid'",
                line=1,
                column=1,
                source=self.source,
                filename=self.filename,
                hint=f"at most {ENUMERATION_LIMIT}: fewer robots or goals",
            )
        rows = valid_configurations(self.kind, n, m, p["capacities"])
        for fact in constraints:
            rows = rows[rows_satisfying(fact, rows, self.robots, self.goals)]
        if rows.shape[0] == 0:
            raise self._empty("no configuration satisfies the 'valid' and 'initially' lines")
        return rows

    def _empty(self, message: str) -> SpecError:
        return SpecError(
            message,
            line=1,
            column=1,
            source=self.source,
            filename=self.filename,
            hint="relax a constraint, or add goals",
        )

    def configurations(self) -> np.ndarray:
        """The valid configurations, ``(k, n)`` goal indices (not for multitask)."""
        if self.kind == "multitask":
            raise InvalidArgumentError(
                "a multitask mission has no fixed configuration set",
                hint="its configurations are chosen every step from the open tasks",
            )
        table = self._table
        if table is not None:
            return table
        p = self.parts
        return valid_configurations(self.kind, len(self.robots), len(self.goals), p["capacities"])

    # -- the logic's view ----------------------------------------------------------------

    @functools.cached_property
    def model(self) -> KripkeModel:
        """The Kripke model: one world per valid configuration, every robot uncertain of
        which, every world designated, after the ``learns`` facts (private announcements
        to the robots named)."""
        if self.kind == "multitask":
            raise InvalidArgumentError(
                "a multitask mission has no explicit model over configurations",
                hint="its configurations are chosen every step from the open tasks",
            )
        p, n, m = self.parts, len(self.robots), len(self.goals)
        total = count_configurations(self.kind, n, m, p["capacities"])
        if self._table is None and total > MAX_CONFIGURATIONS:  # refuse before enumerating
            raise InvalidArgumentError(
                f"{total} configurations exceed the explicit limit of {MAX_CONFIGURATIONS}",
                hint="the simulator needs no model; check claims on a smaller mission",
            )
        model = configuration_model(self.robots, self.goals, self.configurations())
        for names, fact in self.parts["learns"]:
            model = model.update(observed(fact, names, self.robots))
        return model

    def event(self, kind: str, robot: str, goal: str, observers) -> ActionModel:
        """The action model of an observation event: ``"settle"`` (``robot`` settles at
        ``goal``) or ``"complete"`` (``goal``, a task, is done; ``robot`` did it),
        observed by the robots ``observers`` (names), the others oblivious."""
        for name, known in ((robot, self.robots), (goal, self.goals)):
            if name not in known:
                raise InvalidArgumentError(
                    f"unknown name {name!r}", hint=f"declared: {', '.join(known)}"
                )
        for name in observers:
            if name not in self.robots:
                raise InvalidArgumentError(
                    f"unknown observer {name!r}", hint=f"robots: {', '.join(self.robots)}"
                )
        if kind == "settle":
            fact = f"assigned({robot}, {goal})"
        elif kind == "complete":
            fact = " & ".join(f"~assigned({r}, {goal})" for r in self.robots)
        else:
            raise InvalidArgumentError(f"unknown event {kind!r}", hint="settle or complete")
        return observed(fact, observers, self.robots)

    def holds(self, formula: Formula | str, model: KripkeModel | None = None) -> bool:
        """Whether ``formula`` holds at every designated world of ``model`` (default the
        mission's initial model)."""
        if isinstance(formula, str):
            formula = parse_formula(formula)
        return (self.model if model is None else model).holds(formula)


def parse_mission(text: str, filename: str = "<string>") -> Mission:
    """Compile the mission written in ``text``.

    Raises
    ------
    ParseError, SpecError
        Located at the offending token, with a hint.
    """
    parts = compile_text(text, filename)
    study = parts.pop("study")
    mission = Mission(
        name=Path(filename).stem if filename != "<string>" else "mission",
        kind=parts["kind"],
        robots=parts["robots"],
        goals=parts["goals"],
        checks=parts["checks"],
        study=Study(
            trials=study.get("trials", Study.trials),
            seed=study.get("seed", Study.seed),
            levels=study.get("levels", Study.levels),
        ),
        filename=filename,
        source=text,
        parts=parts,
    )
    _check_levels(mission, study)
    mission.scenario()  # validate the world now: a robot outside it, NaN, ...
    return mission


def _mission_streams(seed: int, n: int) -> list[np.random.Generator]:
    """Two independent generators of trial ``seed``: who knows which goal, who is ad hoc."""
    sequence = trial_streams(seed, n).mission.bit_generator.seed_seq
    return [np.random.default_rng(child) for child in sequence.spawn(2)]


def _random_knowledge(stream, n: int, m: int) -> np.ndarray:
    """Per goal, each robot knows it with probability 1/2; nobody: one robot at random."""
    known = stream.random((m, n)) < 0.5
    nobody = ~known.any(axis=1)
    known[np.flatnonzero(nobody), stream.integers(n, size=int(nobody.sum()))] = True
    return known.T.copy()


def _check_levels(mission: Mission, study: dict) -> None:
    tokens = list(study["levels_token"].children) if "levels_token" in study else []
    tokens += [token for _, _, token in mission.parts["teammates"]]
    for token in tokens:
        if str(token).replace("_", "-") not in REASONING:
            raise SpecError(
                f"unknown reasoning level '{token}'",
                line=token.line,
                column=token.column,
                source=mission.source,
                filename=mission.filename,
                hint="levels: " + ", ".join(r.replace("-", "_") for r in REASONING),
            )


def load_mission(path: str | Path) -> Mission:
    """Compile the mission file at ``path``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> spec = "mission rendezvous\\nrobot a: range at random\\ngoal x at (3, 3)\\n"
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d, "tiny.epi"); _ = p.write_text(spec)
    ...     load_mission(p).name
    'tiny'
    """
    _, text = read_input(path, "run", ("mission",))
    return parse_mission(text, str(path))
