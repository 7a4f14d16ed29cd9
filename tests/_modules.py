"""Names of every module of the installed epistemica package (a test helper)."""

from __future__ import annotations

import importlib
import pkgutil

LAYERS = ("epistemica", "epistemica.del_", "epistemica.aif", "epistemica.sim")


def all_modules() -> list[str]:
    """Each layer is its own folder, so walk each one's path rather than the root's only."""
    names = set(LAYERS)
    for layer in LAYERS:
        package = importlib.import_module(layer)
        for info in pkgutil.walk_packages(package.__path__, layer + "."):
            if not info.name.endswith("__main__"):
                names.add(info.name)
    return sorted(names)
