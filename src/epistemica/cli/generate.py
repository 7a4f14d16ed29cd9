"""``epistemica generate FAMILY --count N --seed S --out DIR``: generated mission files
(:mod:`epistemica.generate`)."""

from __future__ import annotations

import argparse

from epistemica.cli.exit import EXIT_OK
from epistemica.generate import Options, generate

__all__ = ["run_generate"]


def run_generate(args: argparse.Namespace) -> int:
    """Write the missions; print how many and where."""
    paths = generate(
        args.family, args.count, args.seed, args.out, Options(args.obstacles, args.discs)
    )
    last = args.seed + args.count - 1
    print(f"wrote {len(paths)} {args.family} missions (generator seeds {args.seed}..{last})")
    print(f"to {args.out}: {paths[0].name} .. {paths[-1].name}")
    return EXIT_OK
