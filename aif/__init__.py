"""Active inference over the set of valid goal configurations.

Imported as ``epistemica.aif``. Depends on ``epistemica.del_`` only.
"""

__all__: list[str] = []
