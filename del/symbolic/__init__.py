"""The symbolic backend: knowledge and belief structures on binary decision diagrams.

See :mod:`epistemica.del_.symbolic.structure`. Imported as ``epistemica.del_.symbolic``;
``KnowledgeStructure`` is also exported by ``epistemica.del_``.
"""

from epistemica.del_.symbolic.structure import KnowledgeStructure

__all__ = ["KnowledgeStructure"]
