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

Bits of codes that are not live worlds carry no meaning; operations whose result
depends on them (boxes, restriction, counting) mask them out.
"""

from __future__ import annotations

from collections.abc import Generator

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import (
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

__all__ = ["Cube", "Space", "announce_node", "bits_node", "pack_bits"]

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


def _hidden(model, agent: str) -> tuple[int, ...]:
    hidden = model.cube.hidden.get(agent)
    if hidden is None:
        raise InvalidArgumentError(
            f"unknown agent {agent!r}", hint=f"the model's agents: {', '.join(model.agents)}"
        )
    return hidden


# A request for a subresult: (model, formula, as bits?, keep in the model's memo?).
Request = tuple
BitsNode = Generator[Request, np.ndarray, np.ndarray]


def bits_node(model, f: Formula, first: Formula | None = None) -> BitsNode:
    """Evaluate one node of ``f`` on bitsets, yielding requests for its subresults.

    The checker's driver answers each request ``(model, g, bits, keep)`` with the bitset
    of ``g`` (no recursion, so any depth works). ``first`` names the child of a binary
    node to evaluate first (the one that needs more live results: fewer stay live).
    """
    cube: Cube = model.cube
    kind = type(f)
    if kind is Atom:
        column = model.atom_column(f.key)
        return cube.zeros() if column is None else cube.atom(column)
    if kind is Top:
        return cube.ones()
    if kind is Bottom:
        return cube.zeros()
    if kind is Not:
        return ~(yield model, f.operand, True, False)
    if kind in (And, Or, Implies, Iff):
        if first is f.right:
            right = yield model, f.right, True, False
            left = yield model, f.left, True, False
        else:
            left = yield model, f.left, True, False
            right = yield model, f.right, True, False
        if kind is And:
            return left & right
        if kind is Or:
            return left | right
        if kind is Implies:
            return ~left | right
        return ~(left ^ right)
    if kind in (Know, Believe):  # one S5 relation per agent: belief is knowledge
        hidden = _hidden(model, f.agent)
        return cube.box((yield model, f.operand, True, False), hidden)
    if kind is KnowWhether:
        hidden = _hidden(model, f.agent)
        inner = yield model, f.operand, True, False
        return cube.box(inner, hidden) | cube.box(~inner, hidden)
    # One S5 relation per agent, so EB = E and CB = C here.
    if kind is Everybody or kind is EverybodyBelieves:
        hiddens = [_hidden(model, agent) for agent in f.group]
        inner = yield model, f.operand, True, False
        result = cube.ones()
        for hidden in hiddens:
            result &= cube.box(inner, hidden)
        return result
    if kind is Common or kind is CommonBelief:
        for agent in f.group:
            _hidden(model, agent)
        return cube.common_box((yield model, f.operand, True, False), f.group)
    if kind is Distributed:
        # Pooling observations: a bit stays hidden only if it is hidden from everyone.
        hidden = set(_hidden(model, f.group[0]))
        for agent in f.group[1:]:
            hidden &= set(_hidden(model, agent))
        return cube.box((yield model, f.operand, True, False), tuple(sorted(hidden)))
    if kind in (Announce, AnnounceDiamond):
        return (yield from announce_node(model, f.announcement, f.operand, kind is Announce))
    raise InvalidArgumentError(f"cannot evaluate {kind.__name__} on bitsets")


def announce_node(model, announcement: Formula, operand: Formula, box: bool = True) -> BitsNode:
    """``[!announcement] operand`` (``box``) or ``<!announcement> operand`` on bitsets.

    The submodel is cached in the model (keyed by the announcement) and shares its
    :class:`Space`, so atoms and hidden bits are not rebuilt for it.
    """
    announced = yield model, announcement, True, True
    key = ("announce-bits", announcement)
    sub = model.derived.get(key)
    if sub is None:
        sub = model.derived[key] = model.cube_submodel(announced)
    inside = yield sub, operand, True, False
    return ~announced | inside if box else announced & inside
