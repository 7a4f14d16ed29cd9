"""The ``.epi`` spec language: the grammar ``spec.lark`` (it imports the formula rules of
``language/formula.lark``), its compiler into a model, actions, a goal and claims, and
``backend.load_spec`` which loads a spec on the explicit or the symbolic backend.

The public names are exported here and by :mod:`epistemica.del_`.
"""

from epistemica.del_.spec._document import Check, Spec, load_spec, parse_spec
from epistemica.del_.spec._names import names_hint

__all__ = ["Check", "Spec", "load_spec", "names_hint", "parse_spec"]
