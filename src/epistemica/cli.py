"""The ``epistemica`` command-line interface.

Exit status: 0 on success, 1 when a checked formula does not hold or no plan exists,
2 on bad input (a malformed spec, an unknown name, a bad option), with the error printed
as ``FILE:LINE:COL: error: ...`` plus a hint and never a Python traceback.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from epistemica import __version__
from epistemica.del_.errors import EpistemicaError

__all__ = ["build_parser", "main"]

EXIT_OK, EXIT_FALSE, EXIT_USAGE = 0, 1, 2

_EPILOG = """\
examples:
  epistemica check specs/puzzles/muddy_children.epi --formula "K[c1] m1"
  epistemica --version
"""


class _Parser(argparse.ArgumentParser):
    """argparse exits with 2 on usage errors already; keep its message short and hinted."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\nhint: run '{self.prog} --help'\n")


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of the ``epistemica`` command."""
    parser = _Parser(
        prog="epistemica",
        description="Epistemic planning and active-inference coordination for multi-robot teams.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"epistemica {__version__}")
    parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handler = getattr(args, "handler", None)
    if handler is None:
        parser.print_help()
        return EXIT_USAGE
    try:
        return int(handler(args))
    except EpistemicaError as err:
        print(err, file=sys.stderr)
        return EXIT_USAGE
