"""Bitset evaluation for models built from observables (the valuation hypercube).

In a model made by :meth:`KripkeModel.from_observables`, every world is a valuation of
``n`` atoms, i.e. a corner of the hypercube ``{0, 1}^n``, and agent ``a`` cannot tell
apart two worlds that differ only on the atoms ``a`` does not observe (its *hidden*
bits). A set of worlds is then a bitset of ``2^n`` bits (bit ``c`` = the world whose
valuation has code ``c``, the first atom being the most significant bit), and
``K[a] f`` is an AND over the hidden dimensions: for each hidden bit ``p``, pair every
code with its neighbour ``c XOR 2^p`` and keep a bit only if both are set. A million
worlds fit in 16,384 machine words, so a box costs microseconds, and public
announcements only shrink the set of live codes: nothing is renumbered.

Bits of codes that are not live worlds carry no meaning; operations whose result
depends on them (boxes, restriction, counting) mask them out.
"""

from __future__ import annotations

import functools

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.formula import (
    And,
    Announce,
    AnnounceDiamond,
    Atom,
    Believe,
    Bottom,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Formula,
    Iff,
    Implies,
    Know,
    KnowWhether,
    Not,
    Or,
    Top,
)

__all__ = ["Cube", "supported"]

_ALL = np.uint64(0xFFFFFFFFFFFFFFFF)
# _LOW[p]: the bits of a 64-bit word whose in-word position has bit p clear.
_LOW = [
    np.uint64(0x5555555555555555),
    np.uint64(0x3333333333333333),
    np.uint64(0x0F0F0F0F0F0F0F0F),
    np.uint64(0x00FF00FF00FF00FF),
    np.uint64(0x0000FFFF0000FFFF),
    np.uint64(0x00000000FFFFFFFF),
]
_SUPPORTED = (
    Atom, Top, Bottom, Not, And, Or, Implies, Iff, Know, Believe, KnowWhether,
    Everybody, Common, Distributed, EverybodyBelieves, CommonBelief, Announce, AnnounceDiamond,
)  # fmt: skip


@functools.lru_cache(maxsize=65536)
def supported(f: Formula) -> bool:
    """Whether every node of ``f`` can be evaluated on bitsets (named actions cannot)."""
    return all(isinstance(g, _SUPPORTED) for g in f.subformulas())


def _unpack(bits: np.ndarray) -> np.ndarray:
    little = bits.astype("<u8", copy=False)
    return np.unpackbits(little.view(np.uint8), bitorder="little").view(bool)


class Cube:
    """The live codes of an observable model and its agents' hidden bits.

    Parameters
    ----------
    n_bits : int
        Number of atoms.
    alive : array of uint64
        Bitset of the codes that are worlds of the model.
    hidden : dict
        Agent -> tuple of code bit positions the agent does not observe.
    """

    def __init__(self, n_bits: int, alive: np.ndarray, hidden: dict[str, tuple[int, ...]]):
        self.n_bits = n_bits
        self.alive = alive
        self.hidden = hidden
        self._codes: np.ndarray | None = None

    @classmethod
    def full(cls, n_bits: int, hidden: dict[str, tuple[int, ...]]) -> Cube:
        """Every valuation of ``n_bits`` atoms is live."""
        words = max(1, (1 << n_bits) >> 6)
        alive = np.full(words, _ALL, dtype=np.uint64)
        if n_bits < 6:
            alive[0] = np.uint64((1 << (1 << n_bits)) - 1)
        return cls(n_bits, alive, hidden)

    def restrict(self, bits: np.ndarray) -> Cube:
        """The same space with only the live codes set in ``bits`` kept."""
        return Cube(self.n_bits, self.alive & bits, self.hidden)

    @property
    def codes(self) -> np.ndarray:
        """The live codes in increasing order (the compact world order)."""
        if self._codes is None:
            self._codes = np.flatnonzero(_unpack(self.alive)).astype(np.intp)
        return self._codes

    def count(self) -> int:
        """The number of live codes."""
        return len(self.codes)

    def test(self, bits: np.ndarray, codes: np.ndarray) -> np.ndarray:
        """The bits at the given codes, as booleans."""
        words = bits[codes >> 6]
        return ((words >> (codes & 63).astype(np.uint64)) & np.uint64(1)).astype(bool)

    def to_mask(self, bits: np.ndarray) -> np.ndarray:
        """The bitset as a boolean mask over the live codes in compact order."""
        return _unpack(bits)[self.codes]

    # -- bit patterns and boxes ---------------------------------------------------------

    def ones(self) -> np.ndarray:
        return np.full(len(self.alive), _ALL, dtype=np.uint64)

    def zeros(self) -> np.ndarray:
        return np.zeros(len(self.alive), dtype=np.uint64)

    def atom(self, column: int) -> np.ndarray:
        """The codes where atom number ``column`` is true."""
        p = self.n_bits - 1 - column
        if p < 6:
            return np.full(len(self.alive), ~_LOW[p], dtype=np.uint64)
        word_has_bit = (np.arange(len(self.alive)) >> (p - 6)) & 1
        return np.where(word_has_bit.astype(bool), _ALL, np.uint64(0))

    def box(self, bits: np.ndarray, hidden: tuple[int, ...]) -> np.ndarray:
        """Codes whose whole class (all values of the hidden bits) lies in ``bits``."""
        x = bits | ~self.alive
        for p in hidden:
            x = _pair_and(x, p)
        return x

    def common_box(self, bits: np.ndarray, group: tuple[str, ...]) -> np.ndarray:
        """``C[group]``: the classes are reflexive, so shrink ``bits`` until stable."""
        x = bits & self.alive
        while True:
            y = x.copy()
            for agent in group:
                y &= self.box(x, self.hidden[agent])
            y &= self.alive
            if np.array_equal(x, y):
                return x
            x = y


def _pair_and(x: np.ndarray, p: int) -> np.ndarray:
    """Keep bit c only if bits c and c XOR 2^p are both set."""
    if p < 6:
        shift = np.uint64(1 << p)
        both = x & (x >> shift) & _LOW[p]
        return both | (both << shift)
    stride = 1 << (p - 6)
    pairs = x.reshape(-1, 2, stride)
    both = pairs[:, 0, :] & pairs[:, 1, :]
    out = np.empty_like(pairs)
    out[:, 0, :] = both
    out[:, 1, :] = both
    return out.reshape(-1)


def evaluate_bits(model, f: Formula) -> np.ndarray:
    """The bitset of ``f`` in an observable model (memoised per model and formula)."""
    key = ("bits", f)
    found = model._memo.get(key)
    if found is None:
        found = _compute(model, f)
        found.setflags(write=False)
        model._memo[key] = found
    return found


def _hidden(model, agent: str) -> tuple[int, ...]:
    hidden = model._cube.hidden.get(agent)
    if hidden is None:
        raise InvalidArgumentError(
            f"unknown agent {agent!r}", hint=f"the model's agents: {', '.join(model.agents)}"
        )
    return hidden


def _compute(model, f: Formula) -> np.ndarray:
    cube: Cube = model._cube
    kind = type(f)
    rec = functools.partial(evaluate_bits, model)
    if kind is Atom:
        column = model._atom_column(f.key)
        return cube.zeros() if column is None else cube.atom(column)
    if kind is Top:
        return cube.ones()
    if kind is Bottom:
        return cube.zeros()
    if kind is Not:
        return ~rec(f.operand)
    if kind is And:
        return rec(f.left) & rec(f.right)
    if kind is Or:
        return rec(f.left) | rec(f.right)
    if kind is Implies:
        return ~rec(f.left) | rec(f.right)
    if kind is Iff:
        return ~(rec(f.left) ^ rec(f.right))
    if kind in (Know, Believe):  # one S5 relation per agent: belief is knowledge
        return cube.box(rec(f.operand), _hidden(model, f.agent))
    if kind is KnowWhether:
        inner, hidden = rec(f.operand), _hidden(model, f.agent)
        return cube.box(inner, hidden) | cube.box(~inner, hidden)
    # One S5 relation per agent, so EB = E and CB = C here.
    if kind is Everybody or kind is EverybodyBelieves:
        inner = rec(f.operand)
        result = cube.ones()
        for agent in f.group:
            result &= cube.box(inner, _hidden(model, agent))
        return result
    if kind is Common or kind is CommonBelief:
        for agent in f.group:
            _hidden(model, agent)
        return cube.common_box(rec(f.operand), f.group)
    if kind is Distributed:
        # Pooling observations: a bit stays hidden only if it is hidden from everyone.
        hidden = set(_hidden(model, f.group[0]))
        for agent in f.group[1:]:
            hidden &= set(_hidden(model, agent))
        return cube.box(rec(f.operand), tuple(sorted(hidden)))
    if kind in (Announce, AnnounceDiamond):
        announced = rec(f.announcement)
        key = ("announce-bits", f.announcement)
        sub = model._derived.get(key)
        if sub is None:
            sub = model._derived[key] = model._cube_submodel(announced)
        inside = evaluate_bits(sub, f.operand)
        if kind is Announce:
            return ~announced | inside
        return announced & inside
    raise InvalidArgumentError(f"cannot evaluate {kind.__name__} on bitsets")
