"""The arguments of the simulator's commands (``run``, the mission options of ``check``,
``simulate``, ``sweep``, ``report``): argparse only, so that building the parser (and
``epistemica --help``) imports none of numpy, scipy or the simulator. Their handlers are
in ``cli.run``, ``cli.simulate`` and ``cli.sweep``, loaded by :data:`epistemica.cli.COMMANDS`
when a command runs.
"""

from __future__ import annotations

import argparse

from epistemica.cli.options import add_scenario_options

__all__ = [
    "add_check_options",
    "add_run_command",
    "add_simulate_command",
    "add_sweep_commands",
    "add_view_command",
    "parse_counts",
]

_LEVELS = """\
levels (a mission file writes - as _, e.g. rules_third):
  goal and multitask missions
    first, second, third      the planning controller at orders 1-3: options (head for a
                              goal, wait) scored by expected free energy over teammates'
                              choices predicted one order down
    rules-first, rules-second, rules-third
                              the rules' one-step controller (expected free energy over
                              the next control, with the search, anchoring and
                              anticipation rules): first/second/third before the switch
    *-shared, *-unpruned      ablations of either (rules-third-shared, third-shared, ...)
    first/second/third-priormode  no expected free energy: the prior's mode
    third-wait                the planner with a 3-step waiting option
    zero, convention, convention+rules, convention-reverse, stationary, paper-*  baselines
    oracle                    full view of poses, goals and closures; least makespan (a
                              reference for completion time)
  collaborative missions
    first, second, third, third-shared, third-priormode   the planning controller
    rules, rules-first, rules-shared   the rules (third, first, third-shared before)
    convention, recruit, convention+rules, oracle, oracle-events   the rules' baselines
"""

_RUN_EXAMPLES = (
    _LEVELS
    + """
examples:
  epistemica run specs/rendezvous.epi                     # its study, table, PNG and GIF
  epistemica run specs/rendezvous.epi specs/nested/private_goal_3.epi   # one after another
  epistemica run specs/task_allocation.epi --trials 50    # the published trial count
  epistemica run specs/multi_task.epi --levels convention,third --no-gif
  epistemica run specs/collaborative/tasks_5.epi          # who knows of which task, animated
  epistemica check specs/sensing_radius.epi --after 30 --seed 3 \\
      --formula "K[r1] assigned(r2, g2)"

exit status: 0 done, 2 bad input
"""
)


_SIMULATE_EXAMPLES = (
    _LEVELS
    + """
examples:
  epistemica simulate --mission allocation --robots 4 --seed 2 --reasoning third
  epistemica simulate --mission rendezvous --robots 3 --goals 4 --reasoning convention --json
  epistemica simulate --mission allocation --robots 5 --png trial.png --gif trial.gif
  epistemica simulate --mission rendezvous --robots 3 --observation honest --sensing-range 10
  epistemica simulate --mission specs/nested/private_goal_3.epi --seed 4 --reasoning first

exit status: 0 the mission succeeded, 1 it failed, 2 bad input
"""
)


_SWEEP_EXAMPLES = """\
examples:
  epistemica sweep --mission rendezvous --robots 2..5 --goals 2..5 \\
      --reasoning zero,convention,rules-third,third --trials 50 --out results.sqlite
  epistemica sweep ... --out results.sqlite --resume       # after an interruption
  epistemica sweep ... --scheduler tcp://127.0.0.1:8786    # on a Dask cluster
  epistemica report results.sqlite --markdown --png results.png
"""


def add_run_command(commands) -> None:
    """Register ``run`` on an argparse subparsers object."""
    cmd = commands.add_parser(
        "run",
        help="run a mission file's study: table, figure and an animated trial",
        description="Compile a mission file, simulate its study (every level on the same "
        "seeds), store the trials in runs/NAME.sqlite (resumed when run again), print the "
        "success table and write runs/NAME.png, and one trial as runs/NAME.gif and runs/NAME.html "
        "(a page to replay in a browser).",
        epilog=_RUN_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    cmd.add_argument(
        "files", nargs="+", metavar="MISSION", help="mission files (.epi), run one after another"
    )
    cmd.add_argument("--trials", type=int, default=None, help="trials per level (default: file)")
    cmd.add_argument(
        "--paper-scale", action="store_true", help="50 trials per level, as the published study"
    )
    cmd.add_argument("--levels", default=None, help="levels, comma-separated (default: file)")
    cmd.add_argument("--seed", type=int, default=None, help="first seed (default: file)")
    cmd.add_argument(
        "--out", default=None, help="results file (default runs/NAME.sqlite; one mission only)"
    )
    cmd.add_argument("--resume", action="store_true", help="add the missing trials to --out")
    _add_execution_options(cmd)
    cmd.add_argument("--no-gif", action="store_true", help="do not animate a trial")
    cmd.add_argument(
        "--trial",
        type=int,
        default=None,
        metavar="SEED",
        help="the seed of the animated trial (default: the first seed where the last level "
        "succeeds and the one before it fails, else where the levels disagree, else the "
        "first seed); the study's last level is animated (a collaborative mission: third, "
        "else rules, by default at the seed where it finishes most steps sooner than first, "
        "else rules-first)",
    )
    cmd.add_argument("--markdown", action="store_true", help="print a markdown table")
    cmd.add_argument(
        "--pdf", action="store_true", help="also write the figure as PDF (vector, for a paper)"
    )
    cmd.add_argument("--svg", action="store_true", help="also write the figure as SVG (vector)")


def _add_execution_options(cmd) -> None:
    """Where trials run and what is stored of them (``run`` and ``sweep``)."""
    cmd.add_argument(
        "--workers", type=_positive, default=None, help="local processes (default: all cores)"
    )
    cmd.add_argument(
        "--scheduler",
        default=None,
        metavar="tcp://HOST:PORT",
        help="run on this Dask scheduler (needs epistemica[cluster])",
    )
    cmd.add_argument(
        "--no-traces",
        action="store_true",
        help="do not store each trial's per-step trace (about 2 kB a trial; huge sweeps)",
    )


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}")
    return value


def add_check_options(check) -> None:
    """The mission-only options of ``check``."""
    check.add_argument(
        "--after",
        type=int,
        default=None,
        metavar="STEPS",
        help="mission files: check after the first STEPS steps of a seeded trial",
    )
    check.add_argument("--seed", type=int, default=None, help="that trial's seed (mission)")
    check.add_argument("--robot", default=None, help="mission: check K[ROBOT] of the formula")
    check.add_argument("--reasoning", default=None, help="mission: level of that trial")


def add_simulate_command(commands) -> None:
    """Register ``simulate`` on an argparse subparsers object."""
    cmd = commands.add_parser(
        "simulate",
        help="simulate one trial of a multi-robot mission",
        description="Simulate one trial of the published protocol (Scenario.paper) at a "
        "reasoning level and report its outcome; optionally draw it.",
        epilog=_SIMULATE_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    cmd.add_argument(
        "--mission",
        default="rendezvous",
        help="rendezvous, allocation, multitask, or a mission file (.epi: its layout and "
        "teammates at --seed)",
    )
    cmd.add_argument("--robots", type=int, default=3, help="team size (default 3)")
    cmd.add_argument(
        "--goals", type=int, default=None, help="goals (default: as many as robots; multitask 20)"
    )
    cmd.add_argument("--seed", type=int, default=0, help="trial seed (default 0)")
    cmd.add_argument(
        "--reasoning",
        default=None,
        help="zero, convention, first, second, third (the planner), rules-first, "
        "rules-second, rules-third (the rules), paper-first, paper-higher, "
        "paper-higher-fixed, ... (below; default third; a mission file: its study's last "
        "level)",
    )
    add_scenario_options(cmd)
    cmd.add_argument("--json", action="store_true", help="print a JSON object")
    cmd.add_argument("--png", metavar="FILE", help="write the trajectories as a PNG")
    cmd.add_argument("--gif", metavar="FILE", help="write an animation with the beliefs")
    cmd.add_argument("--force", action="store_true", help="replace existing --png/--gif files")


def parse_counts(text: str) -> list[int]:
    """``"2,3,5"`` or ``"2..5"`` (or a mix, ``"2..4,8"``) as a list of integers.

    Examples
    --------
    >>> parse_counts("2..4,8")
    [2, 3, 4, 8]
    """
    out: list[int] = []
    for part in text.split(","):
        low, dots, high = part.strip().partition("..")
        try:
            a, b = int(low), int(high) if dots else int(low)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"expected numbers like 2,3,5 or 2..5, got {text!r}"
            ) from None
        if a < 1 or b < a or b - a > 1000:
            raise argparse.ArgumentTypeError(f"expected an increasing range >= 1, got {part!r}")
        out.extend(range(a, b + 1))
    return out


def _names(text: str) -> list[str]:
    return [t.strip() for t in text.split(",") if t.strip()]


def add_sweep_commands(commands) -> None:
    """Register ``sweep`` and ``report`` on an argparse subparsers object."""
    sweep = commands.add_parser(
        "sweep",
        help="run a Monte Carlo grid of simulated trials into an SQLite file",
        description="Run every trial of a grid (paper-protocol scenarios) and store one row "
        "per trial; interrupted sweeps resume with --resume.",
        epilog=_SWEEP_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sweep.add_argument(
        "--mission",
        type=_names,
        default=["rendezvous"],
        help="rendezvous, allocation, multitask (comma-separated), or mission files "
        "(.epi) whose robots are r1..rN",
    )
    sweep.add_argument(
        "--robots",
        type=parse_counts,
        default=None,
        help="team sizes, e.g. 2..5 or 2,3,5 (default 2; a mission file: its N)",
    )
    sweep.add_argument(
        "--goals",
        type=parse_counts,
        default=None,
        help="goal counts (default: as many as robots; multitask 20)",
    )
    sweep.add_argument(
        "--reasoning",
        type=_names,
        default=None,
        help="levels, comma-separated (default zero,convention,third; a mission file: its own)",
    )
    sweep.add_argument(
        "--trials", type=int, default=None, help="seeds per cell (default 50; a file: its own)"
    )
    sweep.add_argument(
        "--seed", type=int, default=None, help="first seed (default 0; a file: its own)"
    )
    sweep.add_argument("--out", required=True, help="results file (SQLite)")
    sweep.add_argument("--resume", action="store_true", help="add the missing trials to --out")
    _add_execution_options(sweep)
    add_scenario_options(sweep)

    report = commands.add_parser(
        "report",
        help="print the success table of a results file and write its figure",
        description="Success rate with 95 % Wilson intervals and mean steps per cell, and "
        "a figure: success (multitask: completion) against team size, one line per level in "
        "study order, each with its own colour, marker and line style. --png, --pdf and --svg "
        "may be combined; without any, RESULTS.png is written.",
    )
    report.add_argument("results", help="an SQLite file written by `epistemica sweep`")
    report.add_argument("--markdown", action="store_true", help="a markdown table")
    report.add_argument(
        "--png", default=None, metavar="FILE", help="figure as PNG (default: RESULTS.png)"
    )
    report.add_argument(
        "--pdf", default=None, metavar="FILE", help="figure as PDF (vector, for a paper)"
    )
    report.add_argument("--svg", default=None, metavar="FILE", help="figure as SVG (vector)")
    report.add_argument("--no-png", action="store_true", help="do not write any figure")
    report.add_argument("--force", action="store_true", help="replace existing figure files")
    report.add_argument(
        "--csv", default=None, metavar="FILE", help="the trials as CSV (needs the data extra)"
    )
    report.add_argument(
        "--parquet",
        default=None,
        metavar="FILE",
        help="the trials as Parquet (needs the data extra: pandas, pyarrow)",
    )


_VIEW_EXAMPLES = """\
examples:
  epistemica view specs/rendezvous.epi                  # simulate its first trial, last level
  epistemica view specs/nested/relocated_3.epi --trial 4 --level first -o relocated.html
  epistemica view trace.json                            # a trace (epistemica.sim.study.trace)
  epistemica view specs/nested/private_goal_3.epi --trial 4 --level third --compare first
  epistemica show specs/puzzles/muddy_children.epi --html muddy.html   # a model's page

exit status: 0 written, 2 bad input
"""


def add_view_command(commands) -> None:
    """Register ``view`` on an argparse subparsers object."""
    cmd = commands.add_parser(
        "view",
        help="write a trial's replay as one self-contained HTML page",
        description="Write one HTML page (script, style and data inline: no server, no "
        "network) replaying a trial: the map with sensing radii, estimates and events, each "
        "robot's belief, the goals it knows and how it learned them, its configuration set and "
        "one robot's model of each teammate's knowledge; a slider scrubs, a button plays and "
        "pauses; --compare draws other levels of the same seed beside it.",
        epilog=_VIEW_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    cmd.add_argument(
        "file",
        metavar="FILE",
        help="a trace (JSON or compressed), a results file storing traces, or a mission file",
    )
    cmd.add_argument("--trial", type=int, default=None, metavar="SEED", help="the trial's seed")
    cmd.add_argument(
        "--level", default=None, help="the trial's level (mission file: default its last)"
    )
    cmd.add_argument(
        "--compare",
        action="append",
        default=None,
        metavar="LEVEL",
        help="also replay the same seed at LEVEL, side by side with one slider (mission or "
        "results file; repeatable)",
    )
    cmd.add_argument("-o", "--out", default=None, help="the page (default: FILE's name .html)")
    cmd.add_argument("--force", action="store_true", help="replace an existing page")
