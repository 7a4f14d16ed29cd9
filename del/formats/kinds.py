"""Which foreign format a path names, by its name alone (nothing is read or imported).

The command line asks this of every input before it knows which reader to load, so this
module imports nothing beyond the standard library: a ``.epi`` spec never pays for the
EPDDL and SMCDEL grammars.

>>> is_epddl("grapevine/domain.PDDL"), is_smcdel("muddy.smcdel.txt"), is_smcdel("m.epi")
(True, True, False)
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["is_epddl", "is_smcdel"]


def is_epddl(path: str | Path) -> bool:
    """Whether a path names an EPDDL file (by its extension, ``.epddl`` or ``.pddl``)."""
    return Path(path).suffix.lower() in (".epddl", ".pddl")


def is_smcdel(path: str | Path) -> bool:
    """Whether a path names an SMCDEL file (``.smcdel``, or SMCDEL's ``.smcdel.txt``)."""
    name = str(path).lower()
    return name.endswith(".smcdel") or name.endswith(".smcdel.txt")
