"""Eager argument checks shared by the active-inference modules (private)."""

from __future__ import annotations

import numpy as np

from epistemica.del_.errors import InvalidArgumentError

__all__: list[str] = []

# Probabilities may be off by rounding; anything further is a caller's mistake.
_SUM_TOLERANCE = 1e-6


def _as_array(value, name: str, ndim: int | None, shape) -> np.ndarray:
    """``value`` as a float array of the given number of dimensions and axis lengths."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidArgumentError(
            f"{name} must be numeric, got {type(value).__name__}",
            hint=f"pass {name} as a list or numpy array of numbers",
        ) from exc
    if ndim is not None and array.ndim != ndim:
        raise InvalidArgumentError(
            f"{name} must have {ndim} dimension(s), got shape {array.shape}",
            hint=f"reshape {name}; see the function's docstring for the expected shape",
        )
    if shape is not None:
        for axis, (got, want) in enumerate(zip(array.shape, shape, strict=False)):
            if want is not None and got != want:
                raise InvalidArgumentError(
                    f"{name} has shape {array.shape}; axis {axis} should have length {want}",
                    hint="the arrays passed together must describe the same robots/goals/states",
                )
    return array


def as_finite(value, name: str, *, ndim: int | None = None, shape=None) -> np.ndarray:
    """Return ``value`` as a float array after checking finiteness and shape."""
    array = _as_array(value, name, ndim, shape)
    if not np.isfinite(array).all():
        raise InvalidArgumentError(
            f"{name} contains NaN or infinite values",
            hint="check the observations for missing or diverged measurements",
        )
    return array


def as_log_values(value, name: str, *, ndim: int | None = None, shape=None) -> np.ndarray:
    """Return ``value`` as an array of log probabilities: ``-inf`` allowed, NaN and ``+inf`` not."""
    array = _as_array(value, name, ndim, shape)
    if np.any(np.isnan(array)) or np.any(array == np.inf):
        raise InvalidArgumentError(
            f"{name} must not contain NaN or +inf",
            hint="log probabilities: use -inf for impossible states and finite values otherwise",
        )
    return array


def positive_int(value, name: str, hint: str) -> int:
    """Return ``value`` as an ``int`` after checking it is an integer >= 1 (not a bool)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InvalidArgumentError(f"{name} must be a positive integer, got {value!r}", hint=hint)
    return int(value)


def as_distribution(value, name: str, *, size: int | None = None) -> np.ndarray:
    """Return ``value`` as a 1-D probability vector (non-negative, summing to one)."""
    if (  # the hot path: a float vector already valid costs a sum and a min, no more
        type(value) is np.ndarray
        and value.dtype == np.float64
        and value.ndim == 1
        and value.size
        and (size is None or value.size == size)
    ):
        with np.errstate(invalid="ignore"):  # inf - inf: NaN, which takes the checks below
            total = value.sum()
        if abs(total - 1.0) <= _SUM_TOLERANCE and value.min() >= 0.0:
            return value / total
    p = as_finite(value, name, ndim=1, shape=(size,))
    if p.size == 0:
        raise InvalidArgumentError(
            f"{name} is empty", hint="a distribution needs at least one state"
        )
    if np.any(p < 0):
        raise InvalidArgumentError(
            f"{name} has negative entries", hint="probabilities must be >= 0"
        )
    total = p.sum()
    if abs(total - 1.0) > _SUM_TOLERANCE:
        raise InvalidArgumentError(
            f"{name} sums to {total:.6g}, not 1",
            hint=f"normalise it first: {name} / {name}.sum()",
        )
    return p / total


def as_nonnegative(value, name: str, *, size: int | None = None) -> np.ndarray:
    """Return a 1-D non-negative vector with at least one positive entry (a likelihood)."""
    v = as_finite(value, name, ndim=1, shape=(size,))
    if np.any(v < 0):
        raise InvalidArgumentError(f"{name} has negative entries", hint="likelihoods are >= 0")
    if v.size == 0 or not np.any(v > 0):
        raise InvalidArgumentError(
            f"{name} is zero everywhere",
            hint="at least one state must be consistent with the observation",
        )
    return v


def nonnegative(value, name: str, hint: str | None = None) -> float:
    """Return ``value`` as a finite float >= 0 (by default a weight that may switch a term off)."""
    x = float(as_finite(value, name, ndim=0))
    if x < 0:
        raise InvalidArgumentError(
            f"{name} must be >= 0, got {value!r}",
            hint=hint or f"pass 0 to switch the {name} term off",
        )
    return x


def positive(value, name: str) -> float:
    """Return ``value`` as a positive finite float."""
    try:
        x = float(value)
    except (TypeError, ValueError) as exc:
        raise InvalidArgumentError(
            f"{name} must be a number, got {value!r}", hint=f"pass a positive {name}"
        ) from exc
    if not np.isfinite(x) or x <= 0:
        raise InvalidArgumentError(
            f"{name} must be positive and finite, got {value!r}", hint=f"pass a positive {name}"
        )
    return x


def as_likelihood_matrix(likelihood, n_states: int | None) -> np.ndarray:
    """Return ``P(o | s)`` as an ``(n_outcomes, n_states)`` array with stochastic columns."""
    a = as_finite(likelihood, "likelihood", ndim=2, shape=(None, n_states))
    if np.any(a < 0) or np.any(np.abs(a.sum(axis=0) - 1.0) > 1e-6):
        raise InvalidArgumentError(
            "likelihood must be P(o | s): non-negative columns that each sum to 1",
            hint="pass an (n_outcomes, n_states) array whose every column is a distribution",
        )
    return a
