"""Batched kinematic multi-robot simulation (not yet implemented).

Imported as ``epistemica.sim``. Depends on ``epistemica.aif`` and ``epistemica.del_``.
"""

__all__: list[str] = []
