"""The JSON documents the command line prints: each tagged with its format and version.

Every ``--json`` output is one object whose first two fields are ``"format"``
(``"epistemica-KIND"``) and ``"version"`` (an integer raised when a field changes meaning
or disappears; new fields may be added within a version). docs/formats.md describes every
field of every kind. ``show --json`` prints a model, whose own format tag
(``epistemica-kripke-1``, ``epistemica-structure-1``) it keeps, so that it loads back.

Examples
--------
>>> print(dumps("simulate", {"success": True}))
{
  "format": "epistemica-simulate",
  "version": 1,
  "success": true
}
"""

from __future__ import annotations

import json
from typing import Any

__all__ = ["VERSIONS", "dumps", "print_json"]

#: The current version of each kind of document.
VERSIONS = {
    "check": 1,  # check FILE --json: the claims of a spec file
    "check-formula": 1,  # check FILE --formula F --json
    "mission-check": 1,  # check MISSION --json: its claims, or --formula
    "plan": 1,  # plan FILE --json
    "implicit-plan": 1,  # plan --implicit --json, and --verify of a plan
    "policy": 1,  # plan --implicit --policy --json, and --verify of a policy
    "simulate": 1,  # simulate --json
}


def dumps(kind: str, document: dict[str, Any]) -> str:
    """``document`` as indented JSON, led by its format tag and version."""
    return json.dumps({"format": f"epistemica-{kind}", "version": VERSIONS[kind], **document},
                      indent=2)  # fmt: skip


def print_json(kind: str, document: dict[str, Any]) -> None:
    """Print :func:`dumps` of ``document``."""
    print(dumps(kind, document))
