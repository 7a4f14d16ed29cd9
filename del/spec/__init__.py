"""The ``.epi`` spec language: the grammar ``spec.lark`` (it imports the formula rules of
``language/formula.lark``), its compiler into a model, actions, a goal and claims, and
``load_spec(path, backend)``, the one loader of the API and the command line (explicit,
symbolic, or ``"auto"`` by size; see :mod:`.backend`), which reads the file once and
bounded (:func:`read_source`).

The public names are exported here and by :mod:`epistemica.del_`.
"""

from epistemica.del_.spec._document import Check, Spec, load_spec, parse_spec
from epistemica.del_.spec._names import names_hint
from epistemica.del_.spec._source import (
    MAX_CLAIMS,
    MAX_SOURCE_BYTES,
    MAX_TOKENS,
    check_claim_count,
    check_token_count,
    read_source,
)

__all__ = [
    "MAX_CLAIMS",
    "MAX_SOURCE_BYTES",
    "MAX_TOKENS",
    "Check",
    "Spec",
    "check_claim_count",
    "check_token_count",
    "load_spec",
    "names_hint",
    "parse_spec",
    "read_source",
]
