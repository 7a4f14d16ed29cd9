"""Generated missions: families of ordinary mission files drawn from a seed.

Each family (:data:`FAMILIES`) draws one mission from a seeded
:class:`numpy.random.Generator` and writes it as a readable mission file (docs/language.md,
"Mission files") whose header comment names the family, the generator seed and every drawn
parameter. Mission ``k`` of ``generate(family, count, seed, out)`` has generator seed
``seed + k``, so a split of a benchmark is a range of seeds, and the same seed gives the same
bytes on every machine. docs/generator.md describes each family's parameters.

Examples
--------
>>> text = mission_text("rendezvous", 7)
>>> text.splitlines()[0]
'# Generated mission, generator seed 7: `epistemica generate rendezvous'
>>> text == mission_text("rendezvous", 7)
True
>>> from epistemica.mission import parse_mission
>>> parse_mission(mission_text("collaborative", 3)).kind.name
'collaborative'
"""

from __future__ import annotations

import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.generate import allocation, asymmetry, collaborative, rendezvous
from epistemica.generate.common import Draw, header
from epistemica.generate.team import PLAIN, Options

__all__ = ["FAMILIES", "MAX_COUNT", "MAX_SEED", "Options", "generate", "mission_text"]

#: Family name -> (its module's ``draw(rng, options)``, a one-line summary).
FAMILIES: dict[str, tuple[Callable[[np.random.Generator, Options], Draw], str]] = {
    "rendezvous": (rendezvous.draw, rendezvous.SUMMARY),
    "allocation": (allocation.draw, allocation.SUMMARY),
    "asymmetry": (asymmetry.draw, asymmetry.SUMMARY),
    "collaborative": (collaborative.draw, collaborative.SUMMARY),
}
#: The most missions one call writes, and the largest generator seed.
MAX_COUNT, MAX_SEED = 100_000, 2**40


def _check(family: str, count: int, seed: int, options: Options) -> None:
    if family not in FAMILIES:
        raise InvalidArgumentError(
            f"unknown mission family {family!r}", hint=f"one of {', '.join(FAMILIES)}"
        )
    for name, value, top in (("count", count, MAX_COUNT), ("seed", seed, MAX_SEED)):
        low = 1 if name == "count" else 0
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= top:
            raise InvalidArgumentError(
                f"{name} must be an integer in {low}..{top:,}, got {value!r}", hint="e.g. 100"
            )
    if family == "collaborative" and any(options):
        raise InvalidArgumentError(
            "the collaborative family draws no obstacles and no disc robots",
            hint="the collaborative simulator has neither yet; drop --obstacles and --discs",
        )
    for name, p in zip(Options._fields, options, strict=True):
        if not 0.0 <= p <= 1.0:
            raise InvalidArgumentError(
                f"--{name} is a probability in [0, 1], got {p!r}", hint="e.g. 0.25"
            )


def _command(family: str, options: Options) -> str:
    flags = [f"--{k} {v:g}" for k, v in zip(Options._fields, options, strict=True) if v]
    return " ".join([family, *flags])


def mission_text(family: str, seed: int, options: Options = PLAIN) -> str:
    """The mission file of ``family`` drawn from generator seed ``seed``."""
    _check(family, 1, seed, options)
    draw, summary = FAMILIES[family]
    rng = np.random.default_rng([zlib.crc32(family.encode()), seed])
    d = draw(rng, options)
    lines = header(_command(family, options), seed, d.parameters, summary)
    return "\n".join([*lines, *d.lines]) + "\n"


def generate(
    family: str, count: int, seed: int, out: str | Path, options: Options = PLAIN
) -> list[Path]:
    """Write missions ``seed`` .. ``seed + count - 1`` of ``family`` into the folder ``out``
    (created; an existing one must be empty: nothing is overwritten); their paths.

    Examples
    --------
    >>> import tempfile
    >>> paths = generate("allocation", 2, 10, tempfile.mkdtemp() + "/a")
    >>> [p.name for p in paths]
    ['allocation_000010.epi', 'allocation_000011.epi']
    """
    _check(family, count, seed, options)
    folder = Path(out)
    if folder.exists() and (not folder.is_dir() or any(folder.iterdir())):
        raise InvalidArgumentError(
            f"{folder} {'holds other files' if folder.is_dir() else 'is not a folder'}",
            hint="name a new or empty folder: generated missions never overwrite anything",
        )
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in range(count):
        path = folder / f"{family}_{seed + k:06d}.epi"
        with open(path, "x", encoding="utf-8", newline="\n") as f:
            f.write(mission_text(family, seed + k, options))
        paths.append(path)
    return paths
