"""scipy's sparse matrices and graph searches, imported on first use.

Importing :mod:`scipy.sparse.csgraph` costs more than the rest of a small ``epistemica
check`` (it pulls in numpy.testing and unittest): relations of small models are dense
numpy arrays and partitions, so most commands never need it. The modules of
``del/explicit/`` call these wrappers, which import scipy when first called.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["breadth_first_order", "connected_components", "coo_matrix", "csr_matrix"]


def csr_matrix(*args: Any, **kwargs: Any):
    """:class:`scipy.sparse.csr_matrix` (same arguments)."""
    import scipy.sparse

    return scipy.sparse.csr_matrix(*args, **kwargs)


def coo_matrix(*args: Any, **kwargs: Any):
    """:class:`scipy.sparse.coo_matrix` (same arguments)."""
    import scipy.sparse

    return scipy.sparse.coo_matrix(*args, **kwargs)


def connected_components(graph: Any, directed: bool = True) -> tuple[int, np.ndarray]:
    """:func:`scipy.sparse.csgraph.connected_components` (number and labels)."""
    from scipy.sparse.csgraph import connected_components as components

    return components(graph, directed=directed)


def breadth_first_order(graph: Any, root: int, directed: bool = True) -> np.ndarray:
    """The nodes reached from ``root`` (:func:`scipy.sparse.csgraph.breadth_first_order`)."""
    from scipy.sparse.csgraph import breadth_first_order as order

    return order(graph, root, directed=directed, return_predecessors=False)
