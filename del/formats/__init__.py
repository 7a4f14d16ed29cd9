"""Foreign formats of the DEL engine: EPDDL (domains, problems, action-type libraries; the
input language of the plank toolkit and of the International Epistemic Planning
Competition) and SMCDEL's text format, read into and written from the objects a ``.epi``
spec compiles into. See docs/epddl.md.

The public names are exported here and by :mod:`epistemica.del_`, each loaded with its
module on first use (PEP 562): :mod:`.kinds`, which the command line asks of every input,
does not load the grammars of the formats.
"""

import importlib

# Each public name and the submodule it lives in.
_SOURCES = {
    "epddl": ("EpddlTask", "load_epddl", "parse_epddl"),
    "epddl_export": ("to_epddl",),
    "smcdel": ("SmcdelFile", "load_smcdel", "parse_smcdel"),
    "smcdel_export": ("to_smcdel",),
}
_WHERE = {name: module for module, names in _SOURCES.items() for name in names}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
    globals()[name] = value
    return value
