"""Mission files: a multi-robot mission written in the epistemic language.

A mission file (``.epi``, grammar ``mission.lark``) declares robots, goals or tasks, which
goal configurations are valid, what each robot senses and knows at the start, the
observation events that update what robots know (action models with triggers), epistemic
claims, and its Monte Carlo study. :func:`load_mission` compiles it into a
:class:`Mission`: the simulator's :class:`~epistemica.sim.Scenario` of each trial, the
epistemic state of the team at the start and after any number of steps of a seeded trial
(the same :class:`~epistemica.del_.EpistemicState` the simulated robots act on), its Kripke
model over the valid configurations, and the claims. ``docs/language.md`` ("Mission
files") is the reference.

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
>>> len(m.configurations()), [m.holds(c.check.formula) == c.check.expected for c in m.checks]
(2, [True, True])
>>> m.scenario().mission, m.scenario().sensors
('allocation', ('range', 'bearing'))
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from epistemica._mission_collaborative import (
    collaborative_parameters,
    collaborative_scenario,
)
from epistemica._mission_compiler import (
    MissionCheck,
    MissionParts,
    compile_events,
    compile_text,
    everyone_observes,
)
from epistemica._mission_plausibility import initial_beliefs, plausibility_model
from epistemica.del_ import (
    Formula,
    KnowledgeStructure,
    KripkeModel,
    PlausibilityModel,
    parse_formula,
)
from epistemica.del_.errors import InvalidArgumentError, SpecError
from epistemica.del_.spec import check_token_count
from epistemica.input_files import MAX_MISSION_TOKENS, read_input
from epistemica.sim.engine.draws import draw_adhoc_teammate, draw_goal_knowledge, draw_layout
from epistemica.sim.engine.events import EventRule, expand
from epistemica.sim.engine.knowledge import TeamKnowledge, initial_knowledge
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.simulate import simulate
from epistemica.sim.engine.trial import Trial
from epistemica.sim.engine.worlds import (
    MAX_CONFIGURATIONS,
    configuration_model,
    configuration_structure,
    fact_mask,
)
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.policies.parameters import ActiveParameters

__all__ = [
    "LIBRARY",
    "Mission",
    "Study",
    "library_event",
    "library_rules",
    "load_mission",
    "parse_mission",
]

#: Configurations beyond which a mission's valid set is not enumerated at compile time.
ENUMERATION_LIMIT = 200_000
#: The library of observation events (``event settle seen by nearby``).
LIBRARY = Path(__file__).with_name("events.epi")


@functools.cache
def library_rules() -> dict[str, EventRule]:
    """The events of the library (``events.epi``), by name."""
    return compile_events(LIBRARY.read_text(encoding="utf-8"), str(LIBRARY))


def library_event(name: str, seen_by: str = "nearby") -> EventRule:
    """An event of the library, observed as written (``"nearby"``) or by every robot
    (``"everyone"``).

    Examples
    --------
    >>> rule = library_event("settle", "everyone")
    >>> rule.trigger.kind, [o.who for o in rule.full], str(rule.full[0].condition)
    ('settles', ['robots'], 'true')
    """
    rules = library_rules()
    if name not in rules or seen_by not in ("nearby", "everyone"):
        raise InvalidArgumentError(
            f"no library event {name!r} seen by {seen_by!r}",
            hint=f"events: {', '.join(rules)}; seen by nearby or everyone",
        )
    return everyone_observes(rules[name]) if seen_by == "everyone" else rules[name]


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
        Reasoning levels to compare (default ``zero, convention, rules-third, first,
        third``: the rules' one-step controller beside the planner).
    """

    trials: int = 20
    seed: int = 0
    levels: tuple[str, ...] = ("zero", "convention", "rules-third", "first", "third")


@dataclass(frozen=True, eq=False)
class Mission:
    """A compiled mission file.

    Attributes
    ----------
    name : str
        The file's stem.
    kind : MissionKind
        The mission's kind (:data:`epistemica.sim.kinds.registry.KINDS`; ``str(kind)`` is
        its name in the file).
    robots, goals : tuple of str
        Names, in declaration order (goals are the tasks of a multitask mission).
    checks : tuple of MissionCheck
        The epistemic claims (``check`` lines), each on the initial model or ``after``
        some steps of a seeded trial.
    study : Study
    filename, source : str
    parts : MissionParts
        Everything the file declares.
    """

    name: str
    kind: MissionKind
    robots: tuple[str, ...]
    goals: tuple[str, ...]
    checks: tuple[MissionCheck, ...]
    study: Study
    filename: str
    source: str = field(repr=False)
    parts: MissionParts = field(repr=False)

    @property
    def team(self) -> int | None:
        """N of the spans ``r1..rN`` this mission was compiled with (None: it has none)."""
        return self.parts.team

    # -- the simulator's view ----------------------------------------------------------

    def scenario(self, seed: int | None = None) -> Scenario:
        """The :class:`~epistemica.sim.Scenario` of trial ``seed`` (default the study's
        first seed): what is placed ``at random`` is drawn from the seed
        (:mod:`epistemica.sim.engine.draws`), the rest as written."""
        seed = self.study.seed if seed is None else int(seed)
        if self.kind.joint:  # its own world: tasks that need several robots
            return collaborative_scenario(self, seed)
        p, n, m = self.parts, len(self.robots), len(self.goals)
        options = dict(p.options)
        layout = draw_layout(seed, n, m, workspace=options.get("workspace", 30.0))
        goals = [g.place or layout.goals[j].tolist() for j, g in enumerate(p.goals)]
        starts = []
        for i, robot in enumerate(p.robots):
            pose = list(robot.place) if robot.place else layout.starts[i].tolist()
            starts.append(pose + [0.0] * (3 - len(pose)))
        known = p.known_goals
        if isinstance(known, str):  # "random": per goal, a non-empty subset of the robots
            known = draw_goal_knowledge(seed, n, m)
        sensors = [
            layout.sensors[i] if r.sensor == "random" else r.sensor for i, r in enumerate(p.robots)
        ]
        try:
            return Scenario(
                self.kind,
                starts,
                goals,
                sensors,
                capacities=p.capacities,
                known_goals=known,
                max_speed=[r.speed for r in p.robots],
                max_turn=[r.turn for r in p.robots],
                valid=self._table,
                events=p.events,
                closed=np.array([g.closed for g in p.goals]),
                told=tuple(
                    (tuple(r in names for r in self.robots), fact) for names, fact in p.learns
                ),
                suggested=initial_beliefs(p.plausibility, self.robots),
                robot_names=self.robots,
                goal_names=self.goals,
                robot_radius=_radii(p.robots),
                obstacles=p.obstacles,
                **options,
            )
        except InvalidArgumentError as exc:
            raise self._located(exc) from None

    def policies(self, seed: int | None = None) -> dict[int, str]:
        """The ad hoc teammate of trial ``seed`` (its ``teammate`` line): robot index to
        level; ``teammate random`` draws the robot from the seed."""
        seed = self.study.seed if seed is None else int(seed)
        out = {}
        for robot, level, _ in self.parts.teammates:
            if robot == "random":
                out[draw_adhoc_teammate(seed, len(self.robots))] = level
            else:
                out[self.robots.index(robot)] = level
        return out

    def _located(self, exc: InvalidArgumentError) -> SpecError:
        """A scenario error, located at the robot it names when possible."""
        line, column = 1, 1
        for index, robot in enumerate(self.parts.robots):
            if f"robot {index} " in exc.message:
                line, column = robot.token.line, robot.token.column
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
        if self.kind.tasks:
            return None
        n, m = len(self.robots), len(self.goals)
        constraints = p.valid + p.initially
        total = self.kind.count(n, m, p.capacities)
        if total == 0:
            raise self._error("the mission kind allows no configuration of these robots")
        if not constraints:
            return None
        if total > ENUMERATION_LIMIT:
            raise self._error(
                f"{total} configurations are too many to constrain with 'valid'",
                f"at most {ENUMERATION_LIMIT}: fewer robots or goals",
            )
        rows = self.kind.configurations(n, m, p.capacities)
        for fact in constraints:
            rows = rows[fact_mask(fact, rows, self.robots, self.goals)]
        if rows.shape[0] == 0:
            raise self._error("no configuration satisfies the 'valid' and 'initially' lines")
        return rows

    def _error(self, message: str, hint: str = "relax a constraint, or add goals") -> SpecError:
        return SpecError(
            message, line=1, column=1, source=self.source, filename=self.filename, hint=hint
        )

    def configurations(self) -> np.ndarray:
        """The valid configurations, ``(k, n)`` goal indices (not for multitask)."""
        table = self._table
        if table is not None:
            return table
        p = self.parts
        return self.kind.configurations(len(self.robots), len(self.goals), p.capacities)

    @functools.cached_property
    def parameters(self) -> ActiveParameters:
        """The active-inference levels' parameters: the defaults, changed by the file's
        ``policy`` lines (a collaborative mission's: ``CollaborativeParameters``)."""
        if self.kind.joint:
            return collaborative_parameters(self, _policy_value)
        out = ActiveParameters()
        for name, text, token in self.parts.policy:
            try:
                out = out.replace(**{name: _policy_value(text)})
            except (InvalidArgumentError, TypeError, ValueError) as exc:
                message = getattr(exc, "message", str(exc))
                raise SpecError(
                    message,
                    line=token.line,
                    column=token.column,
                    source=self.source,
                    filename=self.filename,
                    hint=getattr(exc, "hint", None) or _POLICY_HINT,
                ) from None
        return out

    # -- the logic's view ----------------------------------------------------------------

    def knowledge(self, seed: int | None = None) -> TeamKnowledge:
        """The team's epistemic state at the start of trial ``seed``: the goals each robot
        knows, the facts it was told (``learns``); in a collaborative mission, no task."""
        if self.kind.joint:  # every task is found while exploring
            return TeamKnowledge(
                self.robots, self.goals, np.zeros((len(self.robots), len(self.goals)))
            )
        return initial_knowledge(self.scenario(seed))

    def trial(self, steps: int, seed: int | None = None, level: str | None = None) -> Trial:
        """The first ``steps`` steps of trial ``seed`` at ``level`` (default the study's
        last level), its ad hoc teammate included; ``Trial.knowledge`` is the state the
        robots acted on."""
        if isinstance(steps, bool) or not isinstance(steps, int | np.integer) or steps < 0:
            raise InvalidArgumentError(f"steps must be an integer >= 0, got {steps!r}", hint="20")
        seed = self.study.seed if seed is None else int(seed)
        level = self.study.levels[-1] if level is None else level
        scenario = self.scenario(seed)
        short = scenario.replace(max_steps=max(min(int(steps), scenario.max_steps), 1))
        if steps == 0:
            short = short.replace(max_steps=1)
        return simulate(
            short, level, seed=seed, policies=self.policies(seed), parameters=self.parameters
        )

    def model_of(self, knowledge: TeamKnowledge) -> KripkeModel | KnowledgeStructure:
        """The model over the valid configurations after what ``knowledge`` holds (the
        group semantics of :mod:`epistemica.del_.state`): a Kripke model, or a knowledge
        structure on BDDs when the configurations are too many to list."""
        if self.kind.tasks:
            raise InvalidArgumentError(
                f"a {self.kind} mission has no explicit model over configurations",
                hint="its configurations are chosen every step from the open tasks",
            )
        p, n, m = self.parts, len(self.robots), len(self.goals)
        total = self.kind.count(n, m, p.capacities)
        if total > MAX_CONFIGURATIONS:  # symbolic: the configurations are never listed
            constraints = p.valid + p.initially
            return configuration_structure(
                self.kind, self.robots, self.goals, knowledge.state, p.capacities, constraints
            )
        return configuration_model(self.robots, self.goals, self.configurations(), knowledge.state)

    @functools.cached_property
    def model(self) -> KripkeModel | PlausibilityModel:
        """The Kripke model at the start of the study's first trial: one world per valid
        configuration, every robot uncertain of which, after the ``learns`` facts and with
        the goals each robot knows of. With ``plausibility`` lines, the plausibility model
        of the same worlds and information cells, ranked by the robots' orders."""
        if not self.parts.plausibility:
            return self.model_of(self.knowledge())
        p = self.parts
        total = self.kind.count(len(self.robots), len(self.goals), p.capacities)
        if total > MAX_CONFIGURATIONS:  # the symbolic backend has no plausibility here yet
            token = p.plausibility[0].token
            raise SpecError(
                f"{total} configurations are too many for a plausibility model (at most "
                f"{MAX_CONFIGURATIONS}: the symbolic backend does not take orders yet)",
                line=token.line, column=token.column, source=self.source,
                filename=self.filename, hint="fewer robots or goals",
            )  # fmt: skip
        # The cells come from the hard facts only: the orders are the ranks, not evidence.
        model = self.model_of(initial_knowledge(self.scenario().replace(suggested=())))
        return plausibility_model(model, p.plausibility)

    def model_after(self, steps: int, seed: int | None = None, level: str | None = None):
        """The model after the first ``steps`` steps of a seeded trial (:meth:`trial`)."""
        if steps == 0:
            return self.model_of(self.knowledge(seed))
        trial = self.trial(steps, seed, level)
        try:
            return self.model_of(trial.knowledge)
        except InvalidArgumentError as exc:  # what was observed rules out every configuration
            raise self._nothing_left(exc, trial) from None

    def _nothing_left(self, exc: InvalidArgumentError, trial: Trial) -> SpecError:
        """The error of a model with no configuration left after ``trial``, located at the
        last event of the trial that closed a goal (the usual cause: a goal that every
        valid configuration needs), else at the top of the file."""
        rules = {rule.name: rule for rule in self.parts.events}
        tokens = dict(self.parts.event_tokens)
        closing = [e for e in trial.events if rules.get(e[1]) and rules[e[1]].closes]
        if not closing:
            return self._error(exc.message, exc.hint or "")
        step, name = closing[-1][:2]
        token = tokens[name]
        return SpecError(
            f"after {trial.steps} steps of trial {trial.seed} no valid configuration is left: "
            f"event '{name}' closed {', '.join(rules[name].closes)} at step {step}, and every "
            "configuration the robots considered needs it",
            line=token.line,
            column=token.column,
            source=self.source,
            filename=self.filename,
            hint="check the model before the event (a smaller --after), or let the event "
            "close a goal the mission can do without (more goals than robots)",
        )

    def holds(
        self, formula: Formula | str, model: KripkeModel | PlausibilityModel | None = None
    ) -> bool:
        """Whether ``formula`` (``closed(GOAL)`` allowed) holds at every designated world of
        ``model`` (default the mission's initial model: with ``plausibility`` lines, the
        plausibility model, where ``B[r | c] f``, ``Sb[r] f`` and ``[^^c] f`` mean what
        docs/language.md says)."""
        tree = parse_formula(formula) if isinstance(formula, str) else formula
        return (self.model if model is None else model).holds(expand(tree, self.robots))


def parse_mission(text: str, filename: str = "<string>", team: int | None = None) -> Mission:
    """Compile the mission written in ``text``; ``team`` is the team size N of its robots
    and goals declared as spans ``r1..rN`` (default: its ``simulate robots N``).

    Raises
    ------
    ParseError, SpecError
        Located at the offending token, with a hint.
    """
    check_token_count(text, filename, "mission file", MAX_MISSION_TOKENS)  # bounded memory
    parts = compile_text(text, filename, library_rules(), team)
    defaults = Study()
    mission = Mission(
        name=Path(filename).stem if filename != "<string>" else "mission",
        kind=parts.kind,
        robots=parts.robot_names,
        goals=parts.goal_names,
        checks=parts.checks,
        study=Study(
            trials=defaults.trials if parts.trials is None else parts.trials,
            seed=defaults.seed if parts.seed is None else parts.seed,
            levels=parts.kind.study_levels
            if parts.levels is None
            else tuple(n for n, _ in parts.levels),
        ),
        filename=filename,
        source=text,
        parts=parts,
    )
    mission.scenario()  # validate the world now: a robot outside it, NaN, ...
    _ = mission.parameters  # and its policy line
    return mission


def _radii(robots) -> list[float] | None:
    """Each robot's ``radius`` (0 where none is given); None when no robot has one."""
    if all(r.radius is None for r in robots):
        return None
    return [r.radius or 0.0 for r in robots]


_POLICY_HINT = "policy options: " + ", ".join(f.name for f in fields(ActiveParameters))


def _policy_value(text: str):
    """A ``policy`` value: a number (whole numbers as int), true, false, none, or a word
    (``revision primacy``)."""
    words = {"true": True, "false": False, "none": None}
    if text.lower() in words:
        return words[text.lower()]
    if text.isidentifier():
        return text
    value = float(text)
    return int(value) if value == int(value) and "." not in text else value


def load_mission(path: str | Path, team: int | None = None) -> Mission:
    """Compile the mission file at ``path`` (``team``: see :func:`parse_mission`).

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
    return parse_mission(text, str(path), team)
