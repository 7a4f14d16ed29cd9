"""epistemica: formal epistemic planning with a probabilistic layer.

Layers, each importing only the ones before it:

- :mod:`epistemica.del_`: dynamic epistemic logic (formulas, Kripke models, planning);
- :mod:`epistemica.aif`: active inference over valid goal configurations;
- :mod:`epistemica.sim`: multi-robot simulation;
- this package root: mission specs and the command-line interface.

The root re-exports the logic layer's API (``epistemica.KripkeModel`` is
``epistemica.del_.KripkeModel``). Names are loaded on first use (PEP 562), so that
``epistemica --help`` starts without numpy, scipy or lark.
"""

import importlib

_DEL = "epistemica.del_"
#: Mission files: ``epistemica.load_mission`` and friends (they import the simulator).
_MISSION = ("Mission", "load_mission", "parse_mission")


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("epistemica")  # one source of truth: pyproject.toml
    except PackageNotFoundError:  # imported from a source tree that was never installed
        return "0+unknown"


def __getattr__(name: str):
    if name == "__version__":
        value = _version()
    elif name == "__all__":
        value = ["__version__", "del_", *_MISSION, *importlib.import_module(_DEL).__all__]
    elif name in _MISSION:
        value = getattr(importlib.import_module("epistemica.mission"), name)
    elif name == "del_":
        value = importlib.import_module(_DEL)
    elif name in importlib.import_module(_DEL).__all__:
        value = getattr(importlib.import_module(_DEL), name)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__getattr__("__all__")})
