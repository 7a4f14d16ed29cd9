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

A model and every submodel announced from it share one :class:`Space` (the agents'
hidden bits and the atoms' bitsets, built once). When few codes are still live, pairing
over all ``2^n`` bits is wasted work: such a cube is *sparse* and the checker evaluates it
on its compact worlds instead (see :meth:`Cube.sparse`).

This module holds the data structure and its bit operations only; formulas are
interpreted by the one evaluator, :mod:`.checker`, through :data:`._sets.BITS`.

Bits of codes that are not live worlds carry no meaning; operations whose result
depends on them (boxes, restriction, counting) mask them out.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Cube", "Space", "pack_bits"]

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
# A cube with fewer live codes than words / _SPARSE is evaluated on its compact worlds:
# a box there costs a few operations per live world, here one per word and hidden bit.
_SPARSE = 4
_POPCOUNT = getattr(np, "bitwise_count", None)


def _unpack(bits: np.ndarray) -> np.ndarray:
    little = bits.astype("<u8", copy=False)
    return np.unpackbits(little.view(np.uint8), bitorder="little").view(bool)


def pack_bits(flags: np.ndarray) -> np.ndarray:
    """Booleans (one per code, a multiple of 64) as a bitset."""
    packed = np.packbits(flags, bitorder="little")
    return packed.view("<u8").astype(np.uint64, copy=False)


class Space:
    """What a cube and all its restrictions share: size, hidden bits, atom bitsets.

    Parameters
    ----------
    n_bits : int
        Number of atoms.
    hidden : dict
        Agent -> tuple of code bit positions the agent does not observe.
    """

    def __init__(self, n_bits: int, hidden: dict[str, tuple[int, ...]]) -> None:
        self.n_bits = n_bits
        self.hidden = hidden
        self.words = max(1, (1 << n_bits) >> 6)
        self._atoms: dict[int, np.ndarray] = {}

    @property
    def nbytes(self) -> int:
        """Bytes of one bitset."""
        return 8 * self.words

    def atom(self, column: int) -> np.ndarray:
        """The codes where atom number ``column`` is true (built once, read-only)."""
        found = self._atoms.get(column)
        if found is None:
            p = self.n_bits - 1 - column
            if p < 6:
                found = np.full(self.words, ~_LOW[p], dtype=np.uint64)
            else:
                word_has_bit = ((np.arange(self.words) >> (p - 6)) & 1).astype(bool)
                found = np.where(word_has_bit, _ALL, np.uint64(0))
            found.setflags(write=False)
            self._atoms[column] = found
        return found


class Cube:
    """The live codes of an observable model within its :class:`Space`.

    Parameters
    ----------
    space : Space
        The shared hypercube.
    alive : array of uint64
        Bitset of the codes that are worlds of the model.
    """

    def __init__(self, space: Space, alive: np.ndarray) -> None:
        self.space = space
        self.alive = alive
        self._codes: np.ndarray | None = None
        self._count: int | None = None

    @property
    def n_bits(self) -> int:
        return self.space.n_bits

    @property
    def hidden(self) -> dict[str, tuple[int, ...]]:
        return self.space.hidden

    @classmethod
    def full(cls, n_bits: int, hidden: dict[str, tuple[int, ...]]) -> Cube:
        """Every valuation of ``n_bits`` atoms is live."""
        space = Space(n_bits, hidden)
        alive = np.full(space.words, _ALL, dtype=np.uint64)
        if n_bits < 6:
            alive[0] = np.uint64((1 << (1 << n_bits)) - 1)
        return cls(space, alive)

    def restrict(self, bits: np.ndarray) -> Cube:
        """The same space with only the live codes set in ``bits`` kept."""
        return Cube(self.space, self.alive & bits)

    @property
    def codes(self) -> np.ndarray:
        """The live codes in increasing order (the compact world order)."""
        if self._codes is None:
            self._codes = np.flatnonzero(_unpack(self.alive)).astype(np.intp)
        return self._codes

    def count(self) -> int:
        """The number of live codes (a popcount: no list of codes is built)."""
        if self._count is None:
            if self._codes is not None:
                self._count = len(self._codes)
            elif _POPCOUNT is not None:
                self._count = int(_POPCOUNT(self.alive).sum())
            else:
                self._count = int(np.count_nonzero(_unpack(self.alive)))
        return self._count

    def sparse(self) -> bool:
        """Whether so few codes are live that compact worlds beat bitsets."""
        return self.count() * _SPARSE < self.space.words

    def closed_under_flip(self, p: int) -> bool:
        """Whether flipping code bit ``p`` of a live code always gives a live code."""
        return bool(np.array_equal(_pair_and(self.alive, p), self.alive))

    def test(self, bits: np.ndarray, codes: np.ndarray) -> np.ndarray:
        """The bits at the given codes, as booleans."""
        words = bits[codes >> 6]
        return ((words >> (codes & 63).astype(np.uint64)) & np.uint64(1)).astype(bool)

    def to_mask(self, bits: np.ndarray) -> np.ndarray:
        """The bitset as a boolean mask over the live codes in compact order."""
        if self._codes is not None and 64 * len(self._codes) < self.space.words:
            return self.test(bits, self._codes)
        # One byte per code, not the eight of a list of codes.
        return _unpack(bits)[_unpack(self.alive)]

    def from_mask(self, mask: np.ndarray) -> np.ndarray:
        """The bitset whose live bits are the compact boolean ``mask``."""
        flags = np.zeros(self.space.words * 64, dtype=bool)
        flags[_unpack(self.alive)] = mask
        return pack_bits(flags)

    # -- bit patterns and boxes ---------------------------------------------------------

    def ones(self) -> np.ndarray:
        return np.full(self.space.words, _ALL, dtype=np.uint64)

    def zeros(self) -> np.ndarray:
        return np.zeros(self.space.words, dtype=np.uint64)

    def atom(self, column: int) -> np.ndarray:
        """The codes where atom number ``column`` is true."""
        return self.space.atom(column)

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
