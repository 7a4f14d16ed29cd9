"""``epistemica export``: a spec written as EPDDL or in SMCDEL's text format.

Helper of :mod:`epistemica.cli`, imported only when the command runs (arguments in
:mod:`epistemica.cli.formats`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from epistemica.cli.exit import EXIT_OK
from epistemica.del_.formats.epddl_export import to_epddl
from epistemica.del_.formats.smcdel_export import to_smcdel
from epistemica.del_.spec import load_spec
from epistemica.output_files import check_output, write_output

__all__ = ["run_export"]


def run_export(args: argparse.Namespace) -> int:
    """Run ``epistemica export`` with parsed arguments; return the exit status."""
    spec = load_spec(args.file)
    out = Path(args.output)
    stem = Path(args.file).stem
    if args.epddl:
        files = {f"{stem}-{part}.epddl": text for part, text in to_epddl(spec, stem).items()}
    else:
        files = {f"{stem}.smcdel": to_smcdel(spec)}
    for name in files:
        check_output(out / name, [args.file], args.force, "-o", create_folder=True)
    for name, text in files.items():
        write_output(out / name, text)
        print(f"wrote {out / name}")
    return EXIT_OK
