"""Foreign formats on the command line: the arguments of EPDDL inputs and of ``export``.

Helper of :mod:`epistemica.cli` (imported when the parser is built, so it imports nothing
heavy). ``check``, ``plan`` and ``show`` accept, besides a ``.epi`` spec, an EPDDL task
(``DOMAIN.epddl PROBLEM.epddl [-l LIBRARY.epddl ...]``) and an SMCDEL file (``.smcdel``),
read by :mod:`epistemica.cli.inputs`; ``export`` (:mod:`epistemica.cli.export`) writes a
spec as EPDDL or in SMCDEL's text format.
"""

from __future__ import annotations

import argparse

__all__ = ["add_export_command", "add_input_options"]


def add_input_options(parser: argparse.ArgumentParser) -> None:
    """The EPDDL arguments of ``check``, ``plan`` and ``show``: a problem and libraries."""
    parser.add_argument(
        "problem",
        nargs="?",
        metavar="PROBLEM",
        help="with an EPDDL domain as first file: the EPDDL problem",
    )
    parser.add_argument(
        "-l",
        "--library",
        action="append",
        default=[],
        metavar="LIB",
        help="an EPDDL action-type library the domain uses (repeatable)",
    )


def add_export_command(commands) -> None:
    """Register ``export`` on an argparse subparsers object."""
    export = commands.add_parser(
        "export",
        help="write a spec as EPDDL (domain, problem, library) or in SMCDEL's text format",
        description="Write a .epi spec in another language: --epddl writes "
        "DIR/NAME-domain.epddl, DIR/NAME-problem.epddl and DIR/NAME-library.epddl (plank "
        "parses them); --smcdel writes DIR/NAME.smcdel (VARS, LAW, OBS and one TRUE? or "
        "VALID? per claim).",
        epilog="examples:\n"
        "  epistemica export --epddl specs/planning/grapevine.epi -o out/\n"
        "  epistemica export --smcdel specs/puzzles/muddy_children.epi -o out/\n",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    export.add_argument("file", metavar="SPEC", help="a spec file (.epi)")
    which = export.add_mutually_exclusive_group(required=True)
    which.add_argument("--epddl", action="store_true", help="write EPDDL")
    which.add_argument("--smcdel", action="store_true", help="write SMCDEL's text format")
    export.add_argument(
        "-o", "--output", default=".", metavar="DIR", help="directory to write to (default .)"
    )
    export.add_argument("--force", action="store_true", help="replace existing files")
