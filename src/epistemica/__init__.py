"""epistemica: formal epistemic planning with a probabilistic layer.

Layers, each importing only the ones before it:

- :mod:`epistemica.del_`: dynamic epistemic logic (formulas, Kripke models, planning);
- :mod:`epistemica.aif`: active inference over valid goal configurations;
- :mod:`epistemica.sim`: multi-robot simulation;
- this package root: mission specs and the command-line interface.
"""

from importlib.metadata import PackageNotFoundError, version

from epistemica import del_
from epistemica.del_ import *  # noqa: F403  (the root re-exports the logic layer's API)
from epistemica.del_ import __all__ as _del_all

try:
    __version__ = version("epistemica")  # one source of truth: pyproject.toml
except PackageNotFoundError:  # imported from a source tree that was never installed
    __version__ = "0+unknown"

#: Mission files (loaded on first use: they import the simulator).
_MISSION = ("Mission", "load_mission", "parse_mission")

__all__ = ["__version__", "del_", *_MISSION, *_del_all]


def __getattr__(name: str):
    if name in _MISSION:
        from epistemica import mission

        return getattr(mission, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
