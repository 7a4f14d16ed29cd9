"""The arguments of ``epistemica generate``: argparse only, so that building the parser
imports nothing heavy. The handler is :func:`epistemica.cli.generate.run_generate`."""

from __future__ import annotations

import argparse

__all__ = ["FAMILY_NAMES", "add_generate_command"]

#: The families of :data:`epistemica.generate.FAMILIES` (repeated here so that ``--help``
#: needs no import; tests/test_generate.py checks they agree).
FAMILY_NAMES = ("rendezvous", "allocation", "asymmetry", "collaborative")

_EXAMPLES = """\
examples:
  epistemica generate rendezvous --count 100 --seed 0 --out missions/rendezvous
  epistemica generate asymmetry --count 5 --seed 7 --obstacles 0.5 --discs 0.5 --out m/
  epistemica check missions/rendezvous/rendezvous_000000.epi
  epistemica run missions/rendezvous/rendezvous_000003.epi

Mission k of a call has generator seed SEED + k and is written to FAMILY_SEED.epi; its header
says the family, the seed and every drawn parameter.

exit status: 0 written, 2 bad input (an unknown family, a count or seed out of range, an
output folder that holds other files: nothing is overwritten)
"""


def add_generate_command(commands) -> None:
    """Register ``generate`` on an argparse subparsers object."""
    cmd = commands.add_parser(
        "generate",
        help="write generated mission files of a family",
        description="Write COUNT mission files of FAMILY drawn from generator seeds SEED, "
        "SEED+1, ... into a new or empty folder (the same seed gives the same bytes).",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    cmd.add_argument("family", metavar="FAMILY", help=f"one of {', '.join(FAMILY_NAMES)}")
    cmd.add_argument("--count", type=int, default=10, help="how many missions (default 10)")
    cmd.add_argument("--seed", type=int, default=0, help="the first generator seed (default 0)")
    cmd.add_argument("--out", required=True, metavar="DIR", help="a new or empty folder")
    for name, what in (("obstacles", "1-3 walls"), ("discs", "disc robots")):
        cmd.add_argument(
            f"--{name}",
            type=float,
            default=0.0,
            metavar="P",
            help=f"probability that a mission has {what} (default 0; goal families only)",
        )
