"""The coarsest stable partition of a labelled graph, by incremental splitting.

Bisimulation contraction (:mod:`~epistemica.del_.explicit.bisimulation`) reduces to this:
given nodes with an initial partition and labelled edges, find the coarsest refinement in
which two nodes of a block reach, for every label, the same set of blocks.

Rounds split blocks in bulk, as numpy operations, and each round looks only at what the
previous one changed (Hopcroft's "all but the largest piece" and Paige and Tarjan's edge
counts): when a block ``P`` splits, the largest piece keeps the name ``P`` and only the
other pieces are *moved*. The next round visits the edges into moved nodes only. For each
such edge ``u -l-> v`` the count of ``u``'s ``l``-edges into ``P`` is decremented, and
the count of those into ``v``'s new block is made; a node ``u`` reached this way then
knows exactly which pieces of ``P`` it still reaches: the new ones it has edges into, and
``P`` itself while the decremented count is positive. Nodes of a block that touched no
moved node reach the same pieces as before, so they stay together. A node moves only into
a piece at most half the size of its block, so every node moves at most ``log2 n`` times
and every edge is visited at most ``log2 n`` times: O(m log n) work in all, spread over
as many rounds as the deepest distinguishing formula needs.

Nodes with the same changes are grouped by a 64-bit hash of their sorted changes, and the
groups are then compared element by element, so the result is exact (a hash collision,
should one ever happen, is detected and resolved with Python tuples).
"""

from __future__ import annotations

import numpy as np

__all__ = ["coarsest_partition", "mix64", "ranges"]

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


def coarsest_partition(
    initial: np.ndarray,
    sources: np.ndarray,
    targets: np.ndarray,
    labels: np.ndarray,
    alone: np.ndarray | None = None,
) -> np.ndarray:
    """Block of each node in the coarsest stable refinement of ``initial``.

    Parameters
    ----------
    initial : array of int
        The initial block of each node, labels ``0..k-1``.
    sources, targets, labels : arrays of int
        Edge ``i`` goes from ``sources[i]`` to ``targets[i]`` with label ``labels[i] >= 0``.
        Edges listed in increasing order of target are used as given (no sorted copy).
    alone : array of bool, optional
        Whether edge ``i`` is the only edge of its source with its label (computed when
        not given; a caller that knows it saves a sort of the edges).

    Returns
    -------
    array of int
        Block labels (not necessarily contiguous) such that two nodes share a block exactly
        when they are related by the largest bisimulation that respects ``initial``.

    Examples
    --------
    A chain ``0 -> 1 -> 2`` whose last node differs from the others initially:

    >>> import numpy as np
    >>> blocks = coarsest_partition(np.array([0, 0, 1]), np.array([0, 1]), np.array([1, 2]),
    ...                             np.array([0, 0]))
    >>> len(set(blocks.tolist()))
    3
    """
    return _Refinement(initial, sources, targets, labels, alone).run()


def ranges(starts: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """The concatenation of ``arange(s, s + l)`` for each pair (vectorised).

    >>> ranges(np.array([5, 0]), np.array([2, 3])).tolist()
    [5, 6, 0, 1, 2]
    """
    lengths = np.asarray(lengths, dtype=np.int64)
    total = int(lengths.sum())
    if not total:
        return np.zeros(0, dtype=np.int64)
    keep = lengths > 0
    starts, lengths = np.asarray(starts, dtype=np.int64)[keep], lengths[keep]
    ends = np.cumsum(lengths)
    step = np.ones(total, dtype=np.int64)
    step[0] = starts[0]
    step[ends[:-1]] = starts[1:] - (starts[:-1] + lengths[:-1]) + 1
    return np.cumsum(step)


def mix64(values: np.ndarray) -> np.ndarray:
    """A fixed pseudo-random 64-bit value per integer (the splitmix64 finaliser)."""
    z = values.astype(np.uint64)  # a copy; then in place, with one scratch array
    z += _GOLDEN
    scratch = z >> np.uint64(30)
    z ^= scratch
    z *= _MIX1
    np.right_shift(z, np.uint64(27), out=scratch)
    z ^= scratch
    z *= _MIX2
    np.right_shift(z, np.uint64(31), out=scratch)
    z ^= scratch
    return z


class _Growing:
    """A numpy array that grows by appending (amortised doubling)."""

    def __init__(self, dtype: type, capacity: int = 16) -> None:
        self.data = np.zeros(max(16, capacity), dtype=dtype)
        self.size = 0

    def append(self, values: np.ndarray) -> int:
        start = self.size
        need = start + len(values)
        if need > len(self.data):
            grown = np.zeros(max(need, 2 * len(self.data)), dtype=self.data.dtype)
            grown[:start] = self.data[:start]
            self.data = grown
        self.data[start:need] = values
        self.size = need
        return start


class _Refinement:
    """The state of one refinement: blocks as a refinable partition, edge counts.

    Memory is what bounds the models it can take (tens of millions of edges): edges are
    stored as 32-bit integers when they fit, and an edge alone in its cell (its source's
    only edge of its label) has no cell stored, since its count can only drop to zero.
    """

    def __init__(
        self,
        initial: np.ndarray,
        sources: np.ndarray,
        targets: np.ndarray,
        labels: np.ndarray,
        alone: np.ndarray | None,
    ) -> None:
        n = len(initial)
        self.blocks = np.asarray(initial, dtype=np.int64).copy()
        index = np.int32 if n < 2**31 else np.int64
        # Edges sorted by target: the edges into a node are a run of positions. (A stable
        # sort merges runs: callers that list edges in runs of sorted targets pay less.)
        targets = np.asarray(targets)
        if len(targets) > 1 and (targets[1:] < targets[:-1]).any():
            by_target = np.argsort(targets, kind="stable")
        else:
            by_target = slice(None)
        self.sources = np.asarray(sources)[by_target].astype(index, copy=False)
        self.targets = targets[by_target].astype(index, copy=False)
        self.labels = np.asarray(labels)[by_target].astype(index, copy=False)
        self.width = int(self.labels.max()) + 1 if len(self.labels) else 1
        # Blocks as contiguous runs of `elements` (a refinable partition).
        self.elements = np.argsort(self.blocks, kind="stable")
        self.position = np.empty(n, dtype=np.int64)
        self.position[self.elements] = np.arange(n)
        self.size = np.zeros(n + 1, dtype=np.int64)
        count = int(self.blocks.max()) + 1 if n else 0
        self.size[:count] = np.bincount(self.blocks, minlength=count)
        self.start = np.zeros(n + 1, dtype=np.int64)
        self.start[1 : count + 1] = np.cumsum(self.size[:count])
        self.n_blocks = count
        self.marked = np.zeros(n, dtype=bool)
        self.into = np.zeros(n + 1, dtype=np.int64)
        self.into[1:] = np.cumsum(np.bincount(self.targets, minlength=n))
        # A cell counts the l-edges of one node into one block; each edge points to its
        # cell. A record (node, key) is coded as one integer, node * span + key, key being
        # block * width + label, so sorting codes sorts by node, then block and label.
        self.span = (n + 1) * self.width
        # Nodes are grouped by one 64-bit sort key: the block, then a digest's top bits.
        self.block_bits = np.uint64(max(1, (n + 1).bit_length()))
        self.digest_bits = np.uint64(64) - self.block_bits
        if (n + 1) * self.span >= 2**63:
            raise OverflowError(f"{n} nodes are too many to code records in 64 bits")
        # An edge that is its source's only edge of its label has a cell of its own: no
        # grouping needed (a world's edge to its successor set, any edge of a chain).
        if alone is None:
            alone = _alone(self.sources, self.labels, self.width)
        else:
            alone = np.asarray(alone, dtype=bool)[by_target]
        self.shared = np.flatnonzero(~alone).astype(index)
        self.alone = alone
        self.cell_of_edge = np.zeros(len(self.sources), dtype=np.int32)
        self.cell_count = _Growing(np.int64, len(self.shared))
        self.cell_code = _Growing(np.int64, len(self.shared))

    def run(self) -> np.ndarray:
        moved = self._split(self._recount(None, first=True))
        while len(moved):
            into = ranges(self.into[moved], self.into[moved + 1] - self.into[moved])
            moved = self._split(self._recount(into, first=False))
        return self.blocks

    def _recount(self, edges: np.ndarray | None, first: bool) -> np.ndarray:
        """New cells for ``edges`` (into moved nodes); return the changes they make as
        record codes: per node, the keys of the blocks it now reaches among the pieces
        concerned (its new cells, and its old cells whose count stays positive). The
        first round (``edges`` None) counts every edge."""
        # An edge alone in its cell: its new cell counts 1, and its old one drops to 0.
        if first:  # every edge
            single_codes, shared = self._codes(np.flatnonzero(self.alone)), self.shared
        else:
            alone = self.alone[edges]
            single_codes, shared = self._codes(edges[alone]), edges[~alone]
            del alone, edges
        if not len(shared):
            return single_codes
        code = self._codes(shared)
        order = np.argsort(code)
        code = code[order]
        starts = np.empty(len(code), dtype=bool)
        starts[0] = True
        np.not_equal(code[1:], code[:-1], out=starts[1:])
        records = code[starts]
        del code
        cell = np.cumsum(starts)
        cell -= 1
        del starts
        base = self.cell_count.append(np.bincount(cell))
        self.cell_code.append(records)
        if self.cell_count.size >= 2**31 and self.cell_of_edge.dtype != np.int64:
            self.cell_of_edge = self.cell_of_edge.astype(np.int64)
        old = None if first else self.cell_of_edge[shared]
        cell += base
        self.cell_of_edge[shared[order]] = cell
        del cell, order
        if first:
            return np.concatenate([single_codes, records])
        touched, lost = _tally(old)
        counts = self.cell_count.data
        counts[touched] -= lost
        still = touched[counts[touched] > 0]  # still reaching the piece that kept the name
        return np.concatenate([single_codes, records, self.cell_code.data[still]])

    def _codes(self, edges: np.ndarray) -> np.ndarray:
        """Record codes of edges: source, then the target's block and the label."""
        code = self.sources[edges].astype(np.int64)
        code *= self.span
        code += self.labels[edges]
        code += self.blocks[self.targets[edges]] * self.width
        return code

    def _split(self, records: np.ndarray) -> np.ndarray:
        """Split blocks by the records of their nodes; return the nodes moved."""
        if not len(records):
            return records
        records.sort()  # a fresh array of this round: sorted in place
        nodes, keys = np.divmod(records, self.span)
        del records
        new_node = np.empty(len(nodes), dtype=bool)
        new_node[0] = True
        np.not_equal(nodes[1:], nodes[:-1], out=new_node[1:])
        begin = np.flatnonzero(new_node)
        del new_node
        length = np.diff(np.append(begin, len(keys)))
        touched = nodes[begin]  # one per node, each with its sorted keys
        del nodes
        digest = np.add.reduceat(mix64(keys), begin) ^ mix64(length)
        block = self.blocks[touched]
        # One sort by (block, the digest's top bits): blocks in order, equal digests together.
        sort_key = (block.astype(np.uint64) << self.digest_bits) | (digest >> self.block_bits)
        grouped = np.argsort(sort_key)
        sort_key = sort_key[grouped]
        touched, block, begin, length = (
            touched[grouped],
            block[grouped],
            begin[grouped],
            length[grouped],
        )
        new_group = np.empty(len(sort_key), dtype=bool)
        new_group[0] = True
        np.not_equal(sort_key[1:], sort_key[:-1], out=new_group[1:])
        group = np.cumsum(new_group) - 1
        wrong = _mismatched(group, begin, length, keys)
        if wrong.any():  # equal truncated digests, different records: regroup those exactly
            group = _regroup_exactly(group, wrong, block, begin, length, keys)
            order = np.lexsort((group, block))
            touched, block, group = touched[order], block[order], group[order]
        return self._apply(touched, block, group)

    def _apply(self, touched: np.ndarray, block: np.ndarray, group: np.ndarray) -> np.ndarray:
        """Split each block into its groups of touched nodes and its untouched rest.

        ``touched`` is sorted by block, then group. The largest piece keeps the block's
        name; the others get new names, and their nodes are returned.
        """
        block_first = np.flatnonzero(np.r_[True, block[1:] != block[:-1]])
        blocks_hit = block[block_first]
        n_touched = np.diff(np.append(block_first, len(block)))
        group_starts = np.r_[True, group[1:] != group[:-1]].astype(np.int64)
        groups_per_block = np.add.reduceat(group_starts, block_first)
        rest = self.size[blocks_hit] - n_touched
        splits = groups_per_block + (rest > 0) > 1
        if not splits.any():
            return np.zeros(0, dtype=np.int64)
        # Lay the touched nodes of each splitting block out at the front of its run.
        in_split = np.repeat(splits, n_touched)
        touched, group = touched[in_split], group[in_split]
        blocks_hit, n_touched, rest = blocks_hit[splits], n_touched[splits], rest[splits]
        front = ranges(self.start[blocks_hit], n_touched)
        self.marked[touched] = True
        occupants = self.elements[front]
        strays = occupants[~self.marked[occupants]]
        limit = np.repeat(self.start[blocks_hit] + n_touched, n_touched)
        outside = touched[self.position[touched] >= limit]
        self.marked[touched] = False
        free = self.position[outside]  # in block order, as strays are
        self.elements[free] = strays
        self.position[strays] = free
        self.elements[front] = touched
        self.position[touched] = front
        # The pieces: each group (consecutive in `front`), then the untouched rest.
        piece_first = np.flatnonzero(np.r_[True, group[1:] != group[:-1]])
        piece_start = front[piece_first]
        piece_size = np.diff(np.append(piece_first, len(group)))
        piece_block = self.blocks[touched[piece_first]]
        has_rest = rest > 0
        piece_start = np.concatenate([piece_start, (self.start[blocks_hit] + n_touched)[has_rest]])
        piece_size = np.concatenate([piece_size, rest[has_rest]])
        piece_block = np.concatenate([piece_block, blocks_hit[has_rest]])
        # The largest piece of each block keeps its name (the first largest, by block order).
        order = np.lexsort((-piece_size, piece_block))
        piece_start, piece_size, piece_block = (
            piece_start[order],
            piece_size[order],
            piece_block[order],
        )
        keeps = np.r_[True, piece_block[1:] != piece_block[:-1]]
        self.start[piece_block[keeps]] = piece_start[keeps]
        self.size[piece_block[keeps]] = piece_size[keeps]
        new_start, new_size = piece_start[~keeps], piece_size[~keeps]
        names = self.n_blocks + np.arange(len(new_start))
        self.n_blocks += len(new_start)
        self.start[names] = new_start
        self.size[names] = new_size
        moved_positions = ranges(new_start, new_size)
        moved = self.elements[moved_positions]
        self.blocks[moved] = np.repeat(names, new_size)
        return moved


def _alone(sources: np.ndarray, labels: np.ndarray, width: int) -> np.ndarray:
    """Whether each edge is its source's only edge of its label."""
    per_label = sources.astype(np.int64) * width + labels
    if len(per_label) and int(per_label.max()) < 8 * len(per_label):
        return np.bincount(per_label)[per_label] == 1
    order = np.argsort(per_label, kind="stable")
    ordered = per_label[order]
    del per_label
    differs = np.r_[True, ordered[1:] != ordered[:-1], True]
    del ordered
    alone = np.empty(len(order), dtype=bool)
    alone[order] = differs[:-1] & differs[1:]
    return alone


def _tally(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct values and how often each occurs (by counting when they are dense)."""
    low, high = int(values.min()), int(values.max())
    if high - low > 4 * len(values):
        return np.unique(values, return_counts=True)
    counts = np.bincount(values - low)
    found = np.flatnonzero(counts)
    return found + low, counts[found]


# Records compared at once by _mismatched (about 40 bytes each in flight).
_COMPARED = 1 << 20


def _mismatched(group: np.ndarray, begin: np.ndarray, length: np.ndarray, keys) -> np.ndarray:
    """Per node, whether its records (``keys[begin:begin+length]``) differ from those of
    the first node of its group (``group`` sorted). Only the other members of groups of
    two or more are compared: a group of one is right by construction."""
    first = np.searchsorted(group, group)
    wrong = np.zeros(len(group), dtype=bool)
    check = np.flatnonzero(first != np.arange(len(group)))
    if not len(check):
        return wrong
    mine_length, rep = length[check], first[check]
    wrong[check] = mine_length != length[rep]
    same = check[~wrong[check]]
    # Compared a piece at a time, so that the copies of the records stay small.
    piece = max(1, _COMPARED // max(1, int(length[same].mean()))) if len(same) else 1
    for i in range(0, len(same), piece):
        part = same[i : i + piece]
        size = length[part]
        mine = keys[ranges(begin[part], size)]
        theirs = keys[ranges(begin[first[part]], size)]
        starts = np.cumsum(size) - size
        wrong[part] = np.logical_or.reduceat(mine != theirs, starts)
    return wrong


def _regroup_exactly(group, wrong, block, begin, length, keys) -> np.ndarray:
    """Split the groups holding a wrongly grouped node by their exact records (Python
    tuples, for the few nodes of those groups); other groups keep their numbers."""
    group = group.copy()
    suspect = np.flatnonzero(np.isin(group, group[wrong]))
    names: dict[tuple, int] = {}
    next_group = int(group.max()) + 1
    for i in suspect.tolist():
        record = (int(block[i]), tuple(keys[begin[i] : begin[i] + length[i]].tolist()))
        group[i] = names.setdefault(record, next_group + len(names))
    return group
