"""Foreign formats of the DEL engine: EPDDL (domains, problems, action-type libraries; the
input language of the plank toolkit and of the International Epistemic Planning
Competition) and SMCDEL's text format, read into and written from the objects a ``.epi``
spec compiles into. See docs/epddl.md.

The public names are exported here and by :mod:`epistemica.del_`.
"""

from epistemica.del_.formats.epddl import EpddlTask, load_epddl, parse_epddl
from epistemica.del_.formats.epddl_export import to_epddl
from epistemica.del_.formats.smcdel import SmcdelFile, load_smcdel, parse_smcdel
from epistemica.del_.formats.smcdel_export import to_smcdel

__all__ = [
    "EpddlTask",
    "SmcdelFile",
    "load_epddl",
    "load_smcdel",
    "parse_epddl",
    "parse_smcdel",
    "to_epddl",
    "to_smcdel",
]
