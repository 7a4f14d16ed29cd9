"""The parameters of the active-inference levels: every rule and constant, in one place.

:class:`ActiveParameters` is a frozen dataclass: the Python API builds one (or changes a
default with :meth:`ActiveParameters.replace`), a mission file sets fields with its
``policy`` line (``policy lone_wait 20 look 0.8``), and the levels of
:mod:`epistemica.sim.policies.levels` take it. Parameters of the expected-free-energy controller
itself (:class:`epistemica.aif.Controller`: ``progress_weight``, ``horizon``, ...) pass
through ``controller``. The defaults were chosen on tuning seeds 1000-1039 of the stress
suite (docs/results.md); one set serves every scenario.

Examples
--------
>>> p = ActiveParameters().replace(lone_wait=20, progress_weight=10.0)
>>> p.lone_wait, dict(p.controller)
(20, {'progress_weight': 10.0})
>>> ActiveParameters().replace(lonewait=3)
Traceback (most recent call last):
...
epistemica.del_.errors.InvalidArgumentError: unknown policy parameter 'lonewait'
hint: did you mean 'lone_wait'? ...
"""

from __future__ import annotations

import difflib
import inspect
import math
from dataclasses import dataclass, field, fields, replace

from epistemica.aif.controller import Controller
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.state.state import REVISIONS

__all__ = ["CONTROLLER_OPTIONS", "ActiveParameters", "names"]

#: Controller arguments a policy may set (everything but the scene it is built for).
CONTROLLER_OPTIONS = tuple(
    name
    for name in inspect.signature(Controller).parameters
    if name not in ("goals", "sensors", "configurations", "order", "controls", "dt")
)


@dataclass(frozen=True)
class ActiveParameters:
    """Rules and constants of the active-inference levels.

    Attributes
    ----------
    prior_scale : float or None
        Metres of total distance per nat of the team prior (teammates are efficient,
        :func:`epistemica.aif.prior.team_log_prior`); ``None``: a uniform prior.
    tie_weight : float
        Nats of the shared tie-breaking preference between equally good configurations.
    memory : float
        Exponent ``rho`` in ``[0, 1]`` of the previous posterior in the next prior: 0
        forgets, 1 is a plain Bayes filter.
    revision : str
        How a robot's belief follows teammates' settles that contradict each other:
        ``"recency"``, the newest that leaves a configuration wins (a lexicographic radical
        upgrade, :func:`epistemica.del_.state.state.soft_in_order`), or ``"primacy"``, the
        oldest is kept (the ablation). Every soft fact is reordered, a mission's
        ``plausibility`` levels too (suggested least plausible first), so the ablation is
        for missions without a plausibility order.
    headings : int
        Heading changes in the control grid.
    pruning : bool
        Reason only over the configurations a robot still believes possible after the
        events it observed; ``False`` is the ablation (level ``*-unpruned``).
    nested : bool
        Model each teammate over the configurations the robot knows that teammate keeps;
        ``False`` is the ablation (``*-shared``): every teammate is taken to have seen
        what the robot saw.
    anticipate : bool
        At order 2 and above, where a teammate cannot conceive of configurations the robot
        keeps (it did not see a goal, or saw it elsewhere), predict its goal from its set
        and take the configurations it will actually join
        (:mod:`epistemica.sim.policies.anticipation`). A teammate that only keeps *more* (it missed
        a settle the robot saw) is not anticipated: it will see for itself. Chosen on
        tuning seeds 1000-1029 (docs/results.md §7); ``False`` is the ablation.
    common_view : bool
        At order 2 and above, take the team prior from what is common knowledge: with a
        teammate out of sight no position is, so every robot is placed at the workspace
        centre (the shared default estimate) and the shared tie-break decides.
    remember_sight : bool
        With ``common_view``: while a teammate is out of sight, take the team prior from the
        poses estimated at the last step the robot saw the whole team within sight of each
        other, rather than from the workspace centre, so the configuration chosen in sight
        is kept out of sight (docs/results.md §6, "Remembered sight"); ``False``: the centre.
    sight_hysteresis : int
        Steps a change of sight must last before the common view follows it (1: at once;
        3 and 6 changed no success rate of the stress suite, docs/results.md §6).
    free_energy : bool
        Choose each move by expected free energy (:class:`epistemica.aif.Controller`);
        ``False`` is the ablation (level ``*-priormode``, and ``convention+rules``): drive
        straight to the robot's own goal in the most probable configuration of the prior
        it was handed, every other rule kept.
    teammate_models : bool
        At order 2 and above, infer each teammate's behaviour online from its observed
        moves: a posterior over a library of types (the team's own level, greedy, the other
        convention, stationary; :mod:`epistemica.aif.teammates`), and infer the
        configuration from the type mixture instead of the team prior alone
        (:mod:`epistemica.sim.policies.teammate_models`). It is evidence: the prior-mode ablation
        (``free_energy=False``) ignores it, and so does a robot on the common view (some
        teammate out of its sight: the team coordinates on what is common knowledge).
        ``False`` is the ablation.
    teammate_sigma : float
        Metres of motion-model error in the teammate models (added in quadrature to the
        observation noise of a step; chosen on tuning seeds, docs/results.md).
    teammate_leak : float
        Rate in ``[0, 1]`` at which each type posterior returns to the type prior every
        step (lets a teammate that changes its behaviour be re-read; docs/results.md).
    search : bool
        Rendezvous with a sensing range: a group that has waited ``lone_wait`` steps at a
        goal without the rest of the team searches for it.
    lone_wait : int
        Steps a group waits before its first search (each search doubles it).
    unaware_wait : int
        The same when the group knows that a teammate it does not see does not know of
        the goal it waits at (that teammate cannot be on its way): it searches sooner.
        Second-order knowledge: used at order 2 and above with nested sets only.
    look : float
        A searcher counts a goal as looked at from this fraction of its sensing range.
    anchor_check : int
        Rendezvous search: a member of the group a searcher left that it still sees
        settle at that goal this many steps after leaving never searches (a greedy or
        stationary teammate); the searcher goes back and waits with it, and searches on
        once it has stood there this many steps without seeing it settle
        (:mod:`epistemica.sim.policies.search`). 0 is the ablation.
    prune_from : int
        From this many valid configurations on, a robot reasons over the plausible ones
        only: those within ``prior_scale * (n + plausible_margin)`` of the least total
        distance (:func:`epistemica.aif.prior.plausible_configurations`).
    plausible_margin : float
        See ``prune_from``.
    log_prior_floor : float
        Nats below the best configuration at which the team prior is floored (keeps every
        probability representable in float32).
    planning : bool
        Choose by planning (:mod:`epistemica.sim.policies.planning`): options (head for a
        goal, or wait) scored by expected free energy over the teammates' choices predicted
        one order down over the sets the robot knows they keep, instead of the one-step
        controller over controls. The anticipation rule (``anticipate``) is then not
        applied: the planner's nested predictions subsume it.
    plan_horizon, plan_particles, plan_wait : int
        Steps of the planner's waiting option (``third-wait``: 3; 1: none); particles that
        score it; its model of teammates (aif.plan_waiting, 0-8; 8, session 53).
    plan_temperature, plan_repair, plan_evidence : float
        The planner's precision, repair time, evidence scale (aif.planning.Planner).
    plan_sigma, plan_noise, plan_progress : float
        Error of the planner's motion model in steps of the mean top speed (motion_evidence);
        weight of the two sightings' variance (as the sensor states it) added to its square
        (1: the stated noise, on since session 48; 0: ablation); weight of the seconds
        driven towards its goal charged for changing it (0, off: no gain measured).
    plan_leak, plan_commitment, plan_convention : float
        Rate in ``[0, 1)`` at which that reading forgets, per planned step; nats the planner
        charges for changing the goal a robot headed for; nats of the prior's convention.
    plan_success : float
        The planner's weight on ``-ln P(the configuration forms)`` in nats beside the
        expected completion time (0: a mismatch costs ``plan_repair`` s; aif.md §6g).
    plan_unseen, plan_hidden, plan_settled, plan_join : int
        Places drawn for a never-seen teammate, predicted as the mean from them: over the
        workspace; where it can be, never in sight (hidden_places, aif.md §6g); 0: off. Plans
        at which a teammate seen settled away from the robot's goal, and nowhere else, is held
        there (PlanningStage.anchors; 0: off); steps a robot outnumbered by teammates seen
        settled at a goal it does not know waits to join them (sim.policies.joining; 3).
    plan_types : float
        Posterior on greedy + stationary at which one seen on a goal is held to it (0: off).
    plan_blind, plan_resight, plan_filter, plan_few : bool
        Predict a never-seen teammate without the robot's evidence (``Planner.plan(blind=)``,
        on); read a move only between two sightings, over their gap (on); read sightings by a
        filter per goal (aif.planning.filter_sightings; results/planning_wrong_decision.md);
        predict a teammate that knows too few goals off those it was not shown (known_slots; on).
    plan_claim : {0, 1, 2, 3, 4, 5, 6}
        Price a contested goal by who reaches it first (aif.md §6g): 0 off; 1 a later one yields;
        2 by P(team); 3 moves read so; 4 else by its types; 5 stationary drives; 6 seen (on, s52).
    plan_meet, plan_anchor, plan_sighted : bool
        Planner levels' rendezvous search (aif.md §6g; the rules' never): searchers that meet
        follow one leader; an anchor outranks a find; look where missing teammates were last
        seen before the other goals (all on; :mod:`epistemica.sim.policies.search`).
    plan_hierarchy, plan_shown : float
        In ``[0, 1]``: weight decay of lower orders in the planner's predictions (0: level-k);
        steps a watching teammate sees the robot head for an option's goal (aif.md §6g; 0: off).
    controller : tuple of (str, value)
        Arguments of :class:`epistemica.aif.Controller` (``progress_weight``,
        ``horizon``, ...), as name-value pairs.
    """

    prior_scale: float | None = 1.0
    tie_weight: float = 1.0
    memory: float = 0.0
    revision: str = "recency"
    headings: int = 16
    pruning: bool = True
    nested: bool = True
    anticipate: bool = True
    common_view: bool = True
    remember_sight: bool = True
    sight_hysteresis: int = 1
    free_energy: bool = True
    teammate_models: bool = True
    teammate_sigma: float = 0.25
    teammate_leak: float = 0.02
    search: bool = True
    lone_wait: int = 15
    unaware_wait: int = 3
    look: float = 0.8
    anchor_check: int = 2
    prune_from: int = 2_000
    plausible_margin: float = 10.0
    log_prior_floor: float = -80.0
    planning: bool = False
    plan_horizon: int = 1
    plan_wait: int = 8
    plan_temperature: float = 0.25
    plan_repair: float = 1.5
    plan_evidence: float = 5.0
    plan_particles: int = 32
    plan_sigma: float = 0.5
    plan_noise: float = 1.0
    plan_progress: float = 0.0
    plan_leak: float = 0.1
    plan_commitment: float = 1.0
    plan_convention: float = 1.0
    plan_hierarchy: float = 0.0
    plan_success: float = 1.0
    plan_unseen: int = 0
    plan_hidden: int = 0
    plan_settled: int = 0
    plan_join: int = 3
    plan_types: float = 0.97
    plan_blind: bool = True
    plan_resight: bool = True
    plan_filter: bool = False
    plan_meet: bool = True
    plan_anchor: bool = True
    plan_sighted: bool = True
    plan_shown: float = 0.0
    plan_claim: int = 6
    plan_few: bool = True
    controller: tuple[tuple[str, object], ...] = field(default=())

    def __post_init__(self) -> None:
        numbers = ("memory", "tie_weight", "look", "plausible_margin", "log_prior_floor",
                   "teammate_sigma", "teammate_leak", "plan_temperature", "plan_repair",
                   "plan_evidence", "plan_sigma", "plan_noise", "plan_leak", "plan_progress",
                   "plan_commitment", "plan_convention", "plan_hierarchy", "plan_success",
                   "plan_types", "plan_shown")  # fmt: skip
        for name in (*numbers, "prior_scale"):
            value = getattr(self, name)
            if isinstance(value, str | bool) or (value is None and name != "prior_scale"):
                raise InvalidArgumentError(
                    f"{name} must be a number, got {value!r}", hint=f"e.g. {name}=1.0"
                )
        if not 0.0 <= float(self.memory) <= 1.0:
            raise InvalidArgumentError(
                f"memory must lie in [0, 1], got {self.memory!r}", hint="0 forgets, 1 filters"
            )
        if self.revision not in REVISIONS:
            raise InvalidArgumentError(
                f"revision must be one of {', '.join(REVISIONS)}, got {self.revision!r}",
                hint="'recency' (the default) or the ablation 'primacy'",
            )
        switches = ("pruning", "nested", "anticipate", "common_view", "remember_sight",
                    "free_energy", "search", "teammate_models", "planning",
                    "plan_blind", "plan_meet", "plan_anchor", "plan_sighted",
                    "plan_resight", "plan_filter", "plan_few")  # fmt: skip
        for name in switches:
            if not isinstance(getattr(self, name), bool):
                raise InvalidArgumentError(
                    f"{name} must be true or false, got {getattr(self, name)!r}",
                    hint=f"e.g. {name}=false (the ablation)",
                )
        counts = ("headings", "lone_wait", "unaware_wait", "prune_from", "sight_hysteresis",
                  "plan_horizon", "plan_particles")  # fmt: skip
        for name in counts:
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise InvalidArgumentError(
                    f"{name} must be an integer >= 1, got {value!r}", hint=f"e.g. {name}=16"
                )
        if not float(self.teammate_sigma) > 0:
            raise InvalidArgumentError(
                f"teammate_sigma must be > 0, got {self.teammate_sigma!r}", hint="e.g. 0.5"
            )
        if not 0.0 <= float(self.teammate_leak) <= 1.0:
            raise InvalidArgumentError(
                f"teammate_leak must lie in [0, 1], got {self.teammate_leak!r}", hint="e.g. 0.02"
            )
        for name in ("tie_weight", "look", "plausible_margin", "log_prior_floor"):
            if not math.isfinite(float(getattr(self, name))):
                raise InvalidArgumentError(f"{name} must be finite", hint="a number")
        if self.prior_scale is not None and not float(self.prior_scale) > 0:
            raise InvalidArgumentError(
                f"prior_scale must be > 0 or None, got {self.prior_scale!r}", hint="e.g. 1.0"
            )
        for name, _ in self.controller:
            if name not in CONTROLLER_OPTIONS:
                raise _unknown(name)
        self._check_planner()

    def _check_planner(self) -> None:
        """The planner's parameters (``plan_*``) and ``anchor_check`` beyond their types."""
        for name in ("plan_unseen", "plan_hidden", "plan_settled", "plan_join", "anchor_check"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise InvalidArgumentError(
                    f"{name} must be an integer >= 0, got {value!r}", hint="e.g. 8; 0: off"
                )
        _check_choice("plan_claim", self.plan_claim, tuple(range(7)), "0 off, 2 by type")
        _check_choice("plan_wait", self.plan_wait, tuple(range(9)), "8 (default); 0 uncorrected")
        for name in ("plan_success", "plan_shown", "plan_noise", "plan_progress"):
            value = float(getattr(self, name))
            if not (math.isfinite(value) and value >= 0):
                raise InvalidArgumentError(f"{name} must be >= 0 and finite", hint="e.g. 3")
        if not 0.0 <= float(self.plan_hierarchy) <= 1.0:
            raise InvalidArgumentError(
                f"plan_hierarchy must lie in [0, 1], got {self.plan_hierarchy!r}", hint="e.g. 0"
            )
        if not 0.0 <= float(self.plan_types) < 1.0:
            raise InvalidArgumentError(
                f"plan_types must lie in [0, 1), got {self.plan_types!r}", hint="e.g. 0.9; 0: off"
            )
        if not 0.0 <= float(self.plan_leak) < 1.0:
            raise InvalidArgumentError(
                f"plan_leak must lie in [0, 1), got {self.plan_leak!r}", hint="e.g. 0.1"
            )
        for name in ("plan_temperature", "plan_repair", "plan_evidence", "plan_sigma"):
            value = float(getattr(self, name))
            if not (math.isfinite(value) and value > 0):
                raise InvalidArgumentError(f"{name} must be > 0 and finite", hint="e.g. 0.5")

    def replace(self, **changes) -> ActiveParameters:
        """A copy with some parameters (or controller arguments) changed, validated."""
        own = {f.name for f in fields(self)} - {"controller"}
        controller = dict(self.controller)
        for name, value in changes.items():
            if name in own:
                continue
            if name not in CONTROLLER_OPTIONS:
                raise _unknown(name)
            controller[name] = value
        kept = {k: v for k, v in changes.items() if k in own}
        return replace(self, **kept, controller=tuple(sorted(controller.items())))


def names() -> list[str]:
    """Every parameter a policy line may set."""
    return [f.name for f in fields(ActiveParameters) if f.name != "controller"] + list(
        CONTROLLER_OPTIONS
    )


def _check_choice(name: str, value, choices: tuple, hint: str) -> None:
    """Raise unless ``value`` is one of the integers ``choices`` (a bool is not one)."""
    if isinstance(value, bool) or value not in choices:
        raise InvalidArgumentError(f"{name} must be one of {choices}, got {value!r}", hint=hint)


def _unknown(name: str) -> InvalidArgumentError:
    close = difflib.get_close_matches(name, names(), n=1)
    hint = f"did you mean '{close[0]}'? " if close else ""
    return InvalidArgumentError(
        f"unknown policy parameter {name!r}", hint=hint + "parameters: " + ", ".join(names())
    )
