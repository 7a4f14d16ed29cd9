"""``epistemica run MISSION`` and ``epistemica check MISSION``: mission files on the CLI.

``run`` compiles a mission file, runs its Monte Carlo comparison of reasoning levels (local
processes, one SQLite row per trial under ``runs/``, resumed when run again), prints the
results table and writes the figure (PNG) and one trial as an animation (GIF) and a replay
page (HTML, beside it the same seed at another level), whatever the mission's kind. ``check`` on a
mission file evaluates its claims, or one formula, on the initial model, or on the model
after the first steps of a seeded trial (each observation event applied by product update).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import NamedTuple

from epistemica.answers import answer, atom_meanings
from epistemica.cli.exit import EXIT_INTERRUPTED
from epistemica.cli.json_output import print_json
from epistemica.cli.sweep import store_trials
from epistemica.del_ import parse_formula
from epistemica.del_.errors import EpistemicaError, InvalidArgumentError
from epistemica.html_view import write_page
from epistemica.mission import load_mission, parse_mission
from epistemica.run import mission_trials
from epistemica.sim.engine.simulate import simulate
from epistemica.sim.study.figures import animate_trace
from epistemica.sim.study.report import disputed_seed, format_table, plot_levels, summarise
from epistemica.sim.study.trace import trial_trace
from epistemica.view import trial_page

__all__ = ["check_mission", "is_mission_file", "run_mission"]

EXIT_OK, EXIT_FALSE = 0, 1


def is_mission_file(path: str) -> bool:
    """Whether the file's first statement is a ``mission`` line."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(_HEAD)  # bounded: /dev/zero has no first line
    except OSError:
        return False
    for line in head.decode("utf-8", errors="replace").splitlines():
        words = line.split("#", 1)[0].split()
        if words:
            return words[0] == "mission"
    return False


#: How much of a file :func:`is_mission_file` reads to find its first statement.
_HEAD = 1 << 16


def run_mission(args: argparse.Namespace) -> int:
    """``run``: each mission file's study in turn (all are compiled first, so a typo in
    the last file is reported before any trial runs)."""
    if args.out is not None and len(args.files) > 1:
        raise InvalidArgumentError(
            "--out names one results file, and several mission files were given",
            hint="drop --out (each mission goes to runs/NAME.sqlite) or run them one by one",
        )
    missions = [load_mission(path) for path in args.files]
    for i, mission in enumerate(missions):
        if i:
            print()
        status = _run_study(mission, args)
        if status != EXIT_OK:
            return status
    return EXIT_OK


def _run_study(mission, args: argparse.Namespace) -> int:
    levels = None if args.levels is None else [t.strip() for t in args.levels.split(",")]
    trials = 50 if args.paper_scale else args.trials
    specs = mission_trials(mission, levels, trials, args.seed)
    out = Path(args.out) if args.out else Path("runs") / f"{mission.name}.sqlite"
    out.parent.mkdir(parents=True, exist_ok=True)
    tasks = mission.kind.tasks
    print(
        f"{mission.filename}: {mission.kind}, {len(mission.robots)} robots, "
        f"{len(mission.goals)} {'tasks' if tasks else 'goals'}; "
        f"{len(specs)} trials into {out}"
    )
    # The default file resumes: a trial's id is its text, level and seed, so a stored row
    # is the same result; an explicit --out is added to only with --resume.
    done = store_trials(specs, out, args.out is None or args.resume, args)
    if done is None:
        return EXIT_INTERRUPTED
    rows = done.rows
    cells = summarise(rows)
    order = {s.reasoning: i for i, s in enumerate(specs)}
    cells.sort(key=lambda c: order.get(c.reasoning, len(order)))
    print(format_table(cells, markdown=args.markdown))
    try:
        vector = [fmt for fmt in ("pdf", "svg") if getattr(args, fmt, False)]
        figures = [out.with_suffix(f".{fmt}") for fmt in ("png", *vector)]
        for path in figures:
            plot_levels(cells, path, mission.name)
        print(f"figure: {', '.join(map(str, figures))}")
        gif = out.with_suffix(".gif")
        if not args.no_gif:
            chosen = _collaborative_trial if mission.kind.joint else _animated_trial
            level, seed, why = chosen(args.trial, rows, specs)
            before = _beside(level, seed, rows, specs)
            _animate(mission, level, seed, gif, before)
            beside = f" ({level} beside {before[0]})" if before else ""
            print(
                f"animation ({level}, seed {seed}{why}): {gif} and page{beside}: "
                f"{gif.with_suffix('.html')}"
            )
    except EpistemicaError as exc:  # no matplotlib: the results stand without pictures
        print(f"figures skipped: {exc}", file=sys.stderr)
    print(done.summary())
    return EXIT_OK


def _animated_trial(chosen: int | None, rows: list[dict], specs) -> tuple[str, int, str]:
    """The level, seed and reason of the animated trial: the study's last (highest) level
    at ``--trial``, else at the seed :func:`~epistemica.sim.study.report.disputed_seed` picks (the
    first where the last level succeeds and the one before it fails, or else where the
    levels disagree)."""
    level = specs[-1].reasoning
    if chosen is not None:
        return level, chosen, ""
    levels = list(dict.fromkeys(s.reasoning for s in specs))
    seed = disputed_seed(rows, levels)
    if seed is None:
        return level, specs[0].seed, ": the levels agree on every seed"
    return level, seed, ": the first where the levels disagree, the last succeeding if it can"


def _beside(level: str, seed: int, rows: list[dict], specs) -> list[str]:
    """The level drawn beside ``level`` on the page of its trial at ``seed``: the highest
    other level that failed there (else the highest other level), so that the page shows
    why one level failed where the other did not."""
    levels = [lv for lv in dict.fromkeys(s.reasoning for s in specs) if lv != level]
    failed = {r["reasoning"] for r in rows if int(r["seed"]) == seed and not r["success"]}
    return ([lv for lv in levels if lv in failed] or levels)[-1:]


def _collaborative_trial(chosen: int | None, rows: list[dict], specs) -> tuple[str, int, str]:
    """The level and seed of a collaborative study's animated trial: ``third`` (else
    ``rules``, else the last level) at ``--trial``, else the seed where it gains most steps
    over ``first`` (else ``rules-first``) among the trials both solve (the first seed when
    it has no such trial)."""
    levels = list(dict.fromkeys(s.reasoning for s in specs))
    level = next((lv for lv in ("third", "rules") if lv in levels), levels[-1])
    if chosen is not None:
        return level, chosen, ""
    base = next((lv for lv in ("first", "rules-first") if lv in levels and lv != level), None)
    steps = {(r["reasoning"], int(r["seed"])): r["steps"] for r in rows if r["success"]}
    gains = {
        seed: steps[(base, seed)] - steps[(level, seed)]
        for _, seed in steps
        if (base, seed) in steps and (level, seed) in steps
    }
    if not gains:
        return level, specs[0].seed, ""
    seed = min(gains, key=lambda s: (-gains[s], s))
    if gains[seed] <= 0:
        return level, seed, f": no sooner than {base} on any seed, the least behind"
    return level, seed, f": {gains[seed]} steps sooner than {base}, the most of any seed"


def _animate(mission, level: str, seed: int, path: Path, others: list[str]) -> None:
    """The GIF of ``level``'s trial at ``seed`` (any kind: the kind's panels); its page,
    with the ``others`` levels' trials of the same seed beside it."""
    scenario = mission.scenario(seed)
    traces = []
    for reasoning in [level, *others]:
        trial = simulate(
            scenario,
            reasoning,
            seed=seed,
            policies=mission.policies(seed),
            parameters=mission.parameters,
        )
        traces.append(trial_trace(scenario, trial))
    animate_trace(traces[0], path, mission=mission.name)
    write_page(path.with_suffix(".html"), trial_page(traces[0], mission.name, traces[1:]))


class _Claim(NamedTuple):
    """One line of ``check``'s answer: a claim of the file, or ``--formula``."""

    name: str
    text: str
    expected: bool | None  # None: a question, not a claim
    holds: bool
    when: str

    @property
    def failed(self) -> bool:
        return self.expected is not None and self.expected != self.holds


def check_mission(args: argparse.Namespace, text: str | None = None) -> int:
    """``check`` on a mission file: its claims, or ``--formula``, now or ``--after`` steps.

    A claim written ``check "..." after N steps [seed S] [level L]: F`` is checked after
    those steps of that seeded trial (default: the study's first seed and last level).
    ``text``: the file's text, already read (a pipe is read once).
    """

    mission = load_mission(args.file) if text is None else parse_mission(text, args.file)
    if args.formula is None and not mission.checks and args.after is None:
        print(f"{args.file}: {mission.kind}, no claims; add 'check \"name\": FORMULA' lines")
        return EXIT_OK
    if args.after is not None and args.after < 0:
        raise InvalidArgumentError("--after must be >= 0", hint="a number of steps")
    models: dict = {}

    def model(after, seed, level):
        key = (after, seed, level)
        if key not in models:
            models[key] = mission.model if after is None else mission.model_after(*key)
        return models[key]

    where = "initially"
    if args.after is not None:
        seed = mission.study.seed if args.seed is None else args.seed
        level = args.reasoning or mission.study.levels[-1]
        where = f"after {args.after} steps of trial {seed} ({level})"
    asked = None
    if args.formula is not None:
        claim, asked = _formula_claim(mission, args, model, where)
        claims = [claim]
    else:
        claims = _file_claims(mission, args, model, where)
    failed = [c for c in claims if c.failed]
    if args.json:
        out = [
            {
                "name": c.name,
                "formula": c.text,
                "expected": c.expected,
                "holds": c.holds,
                "ok": None if c.expected is None else not c.failed,
                "when": c.when,
            }
            for c in claims
        ]
        if asked is not None:
            out[0].update(true_in=asked[0], designated=asked[1])
        print_json("mission-check", {"file": args.file, "when": where, "claims": out})
        return EXIT_FALSE if failed else EXIT_OK
    chosen = model(args.after, args.seed, args.reasoning)
    print(f"{args.file}: {where}; {chosen.n_worlds} worlds, robots {', '.join(mission.robots)}")
    _print_claims(claims, where, asked, args.formula, mission.robots)
    if args.formula is None or args.expect is not None:
        print(f"{len(claims) - len(failed)} passed, {len(failed)} failed")
    return EXIT_FALSE if failed else EXIT_OK


def _formula_claim(mission, args: argparse.Namespace, model, where: str) -> tuple[_Claim, tuple]:
    """``--formula`` (as ``--robot`` knows it) on the chosen model, and :func:`answer`'s
    count of the designated configurations where it is true."""
    formula = parse_formula(args.formula)
    if args.robot is not None:
        if args.robot not in mission.robots:
            raise InvalidArgumentError(
                f"unknown robot {args.robot!r}", hint=f"robots: {', '.join(mission.robots)}"
            )
        formula = parse_formula(f"K[{args.robot}] ({args.formula})")
    chosen = model(args.after, args.seed, args.reasoning)
    expected = None if args.expect is None else args.expect == "true"  # None: a question
    claim = _Claim("--formula", str(formula), expected, mission.holds(formula, chosen), where)
    # A mission's model has a designated world per configuration: say how many.
    return claim, answer(chosen, formula, mission.robots)


def _file_claims(mission, args: argparse.Namespace, model, where: str) -> list[_Claim]:
    """The file's claims, each at its own moment unless ``--after`` sets one for all."""
    claims = []
    for c in mission.checks:
        after, seed, level = c.after, c.seed, c.level
        if args.after is not None:  # --after overrides every claim's own moment
            after, seed, level = args.after, args.seed, args.reasoning
        label = (
            where
            if after is None or args.after is not None
            else (f"after {after} steps of trial {mission.study.seed if seed is None else seed}")
        )
        holds = mission.holds(c.check.formula, model(after, seed, level))
        claims.append(_Claim(c.check.name, c.check.text, c.check.expected, holds, label))
    return claims


def _print_claims(claims: list[_Claim], where: str, asked, formula, robots) -> None:
    """One line per claim (``ok``/``FAIL`` when it has an expected value); for ``--formula``
    the count of configurations and what its atoms stand for."""
    for claim in claims:
        if claim.expected is None:
            mark = "    "
        else:
            mark = "FAIL" if claim.failed else "ok  "
        moment = "" if claim.when == where else f" [{claim.when}]"
        word = "true " if claim.holds else "false"
        if asked is not None and 0 < asked[0] < asked[1]:
            word = "neither"
        print(f"  {mark}  {word}  {claim.name}{moment}: {claim.text}")
    if asked is not None:
        print(f"          {asked[2]}")
        for line in atom_meanings(formula, robots):
            print(f"          {line}")
