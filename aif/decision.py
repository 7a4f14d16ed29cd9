"""A robot's decision: the control chosen from the expected free energy of each candidate.

Shared by the one-robot call (:meth:`Controller.decide <epistemica.aif.Controller.decide>`)
and the team call (:mod:`~epistemica.aif.team`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import softmax

from epistemica.aif.free_energy import select_policy
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["Decision", "choose"]


@dataclass(frozen=True)
class Decision:
    """The outcome of one decision.

    Attributes
    ----------
    control : tuple of float
        The chosen ``(speed, heading change)``.
    index : int
        Its row in :attr:`Controller.controls`.
    G : numpy.ndarray
        Expected free energy of every candidate (best continuation when ``horizon > 1``).
    q_pi : numpy.ndarray
        Policy posterior ``softmax(-gamma G)`` over the candidates.
    belief : numpy.ndarray
        The robot's current belief over the valid configurations.
    focal : int
        Row of the focal (most probable) configuration.
    """

    control: tuple[float, float]
    index: int
    G: np.ndarray
    q_pi: np.ndarray
    belief: np.ndarray
    focal: int


def choose(
    controls: np.ndarray, gamma: float, G: np.ndarray, beliefs, focals, rngs
) -> list[Decision]:
    """Decisions from the candidates' ``G (R, c)``: least (first on ties), or sampled from
    ``softmax(-gamma G)`` with each robot's generator."""
    finite = np.isfinite(G)
    if not finite.any(axis=1).all():
        raise InvalidArgumentError(
            "no candidate control has a finite expected free energy",
            hint="check the weights and the controls",
        )
    least = np.where(finite, G, np.inf).min(axis=1, keepdims=True)
    shifted = np.where(finite, G - least, 0.0)
    with np.errstate(over="ignore"):  # a huge precision: logits -inf, never NaN
        logits = np.where(finite, -gamma * shifted, -np.inf)
    q_pi = softmax(logits, axis=1)
    first = np.argmax(G == least, axis=1)
    out = []
    for r, rng in enumerate(rngs):
        index = int(first[r]) if rng is None else select_policy(q_pi[r], rng)
        control = (float(controls[index, 0]), float(controls[index, 1]))
        out.append(Decision(control, index, G[r], q_pi[r], beliefs[r], int(focals[r])))
    return out
