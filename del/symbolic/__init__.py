"""The symbolic backend: knowledge and belief structures on binary decision diagrams.

:mod:`~epistemica.del_.symbolic.structure` holds the data and algorithms
(:class:`~epistemica.del_.symbolic.structure.SymbolicModel`); the public class is
:class:`epistemica.del_.KnowledgeStructure`, which adds the conversions to and from Kripke
models (see :mod:`epistemica.del_.models`).
"""
