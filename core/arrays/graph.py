"""Graph and index helpers over numpy arrays: no Python loop per node, edge or pair.

Nodes are ``0 .. count-1``; edges are ``(m, 2) int`` arrays of node pairs.
"""

import math

import numpy as np


def index_type(count):
    """int32 for indices below ``count`` where they fit (half the bytes of int64), else int64."""
    return np.int32 if count < 2**31 else np.int64


def connected_components(count, edges):
    """Label the connected components of an undirected graph.

    Parameters
    ----------
    count : int
        Number of nodes.
    edges : (m, 2) int
        Node pairs; self-loops and repeats are allowed.

    Returns
    -------
    labels : (count,) int64
        Component of each node, numbered ``0 ..`` in order of each component's
        smallest node, so the result does not depend on edge order.

    Union-find by hooking roots onto smaller roots and pointer jumping, all
    vectorised: O((count + m) log count) in the worst case.
    """
    # int32 indices where they fit: every pass gathers and compares, so half the bytes is a third off
    index = index_type(count)
    parent = np.arange(count, dtype=index)
    edges = np.asarray(edges).reshape(-1, 2)
    u, v = edges[:, 0].astype(index), edges[:, 1].astype(index)
    root_u, root_v = u, v                     # every node its own root at first: no gather
    while True:
        pending = root_u != root_v
        if not pending.any():
            break
        u, v, root_u, root_v = u[pending], v[pending], root_u[pending], root_v[pending]
        # ``high`` is a root: hook it under the smallest root it touches.
        np.minimum.at(parent, np.maximum(root_u, root_v), np.minimum(root_u, root_v))
        parent = _compress(parent)
        root_u, root_v = parent[u], parent[v]
    # Every node now points at its root, the smallest node of its component: number the roots in order.
    is_root = parent == np.arange(count, dtype=index)
    return (np.cumsum(is_root, dtype=np.int64) - 1)[parent]


def _compress(parent):
    """Pointer jumping until every node points straight at its root."""
    while True:
        grand = parent[parent]
        if np.array_equal(grand, parent):
            return parent
        parent = grand


def index_in_runs(counts):
    """Index of each item within its run, for runs of ``counts`` (n,) items laid end to end.

    ``index_in_runs([2, 0, 3]) == [0, 1, 0, 1, 2]``; (sum(counts),) int64.
    """
    counts = np.asarray(counts, dtype=np.int64)
    return np.arange(int(counts.sum()), dtype=np.int64) - np.repeat(np.cumsum(counts) - counts, counts)


def sort_order(*keys, stable=True):
    """Order sorting by several non-negative integer keys, most significant first.

    The same as ``np.lexsort(keys[::-1])``; when the keys' ranges multiply to
    less than 2**62 they are folded into one int64 key and sorted once, two to
    three times faster on millions of entries.  A least significant key
    already in order (a face index along the triangles Blender lists face by
    face) is left out: sorting stably by the others keeps it in order.

    How the folded key is sorted follows its order (:func:`in_mesh_order`):
    keys read along a mesh (vertex and face indices of neighbouring triangles
    are close) go to numpy's stable sort, a merge sort that follows the runs
    already in order: on the keys of the report's meshes and a 1M-triangle
    Suzanne it took a fifth to a half of the time of the unstable one.  Keys in
    no order (a shuffled mesh) go to :func:`radix_order` from :data:`RADIX_FROM`
    entries up, two to three times as fast as either of numpy's sorts there.

    Parameters
    ----------
    *keys : (n,) int arrays, each >= 0
    stable : bool
        Entries with equal keys keep their order.  A caller that cannot tell
        such entries apart passes False; every sort used is stable today, so
        it only says that a faster unstable one would do.

    Returns
    -------
    (n,) int64
    """
    keys = [np.asarray(key, dtype=np.int64) for key in keys]
    if not len(keys[0]):
        return np.zeros(0, dtype=np.int64)
    while len(keys) > 1 and bool((keys[-1][1:] >= keys[-1][:-1]).all()):
        keys.pop()
    spans = [int(key.max()) + 1 for key in keys]
    folded_span = math.prod(spans)                          # Python ints: exact
    if folded_span >= 2**62:
        return np.lexsort(keys[::-1])
    folded = keys[0].copy() if len(keys) > 1 else keys[0]         # one key is sorted as it is
    for key, span in zip(keys[1:], spans[1:]):
        folded *= span
        folded += key
    if len(folded) >= RADIX_FROM and not in_mesh_order(folded, folded_span):
        return radix_order(folded, folded_span)
    return np.argsort(folded, kind="stable")


def in_mesh_order(key, span, samples=4096, near=2.0**-10, share=0.25):
    """Whether ``key`` (n,) int64 in ``[0, span)`` looks read along a mesh: of ``samples`` neighbouring
    pairs spread over it, at least ``share`` differ by less than ``near`` of the span (pairs of keys in no
    order do so about ``2 * near`` of the time; in the bakes of the report's meshes and a 1M-triangle Suzanne 0.5 to 1)."""
    if len(key) < 2:
        return True
    at = np.linspace(0, len(key) - 2, min(samples, len(key) - 1)).astype(np.int64)
    return float((np.abs(key[at + 1] - key[at]) < near * span).mean()) >= share


#: From this many entries :func:`sort_order` sorts keys in no order by :func:`radix_order`: its fixed cost
#: (a count of 65536 buckets a pass) is paid back from a few ten thousand entries.
RADIX_FROM = 1 << 16


def radix_order(key, span):
    """Stable sorting order of a non-negative int64 ``key`` (n,) below ``span``, 16 bits a pass.

    numpy's stable sort of 16-bit integers is a radix sort (one counting pass,
    no comparisons), so sorting by each 16-bit digit in turn, least significant
    first, is a radix sort of the whole key: on 1.5 to 3 million keys of a bake
    under 2**32 it took a third of the time of ``np.argsort`` (either kind), and
    under 2**42 two thirds.  (n,) int64, the same as ``np.argsort(key, kind="stable")``.
    """
    passes = max(1, (int(span) - 1).bit_length() + 15 >> 4)
    order = np.argsort((key & 0xFFFF).astype(np.uint16), kind="stable")
    if passes > 1 and len(key) < 2**31:
        order = order.astype(np.int32)                  # half the bytes to gather in every later pass
    for shift in range(16, 16 * passes, 16):
        digit = ((key >> shift) & 0xFFFF).astype(np.uint16)
        order = order[np.argsort(digit[order], kind="stable")]
    return order.astype(np.int64)


def row_labels(*keys):
    """(n,) int64: one label per distinct row of ``keys`` ((n,) non-negative ints each, most significant first),
    numbered ``0 ..`` in the rows' sorted order; rows equal in every key share a label."""
    keys = [np.asarray(key, dtype=np.int64) for key in keys]
    order = sort_order(*keys)
    new = np.zeros(len(order), dtype=bool)
    new[:1] = True
    for key in keys:
        ordered = key[order]
        new[1:] |= ordered[1:] != ordered[:-1]
    labels = np.empty(len(order), dtype=np.int64)
    labels[order] = np.cumsum(new) - 1
    return labels


def group_starts(sorted_keys):
    """Start index of each run of equal values in a sorted 1D array, plus the end."""
    sorted_keys = np.asarray(sorted_keys)
    if sorted_keys.size == 0:
        return np.zeros(1, dtype=np.int64)
    change = np.flatnonzero(sorted_keys[1:] != sorted_keys[:-1]) + 1
    return np.concatenate(([0], change, [sorted_keys.size])).astype(np.int64)


def pairs_within_groups(starts):
    """All index pairs ``(i, j)``, ``i < j``, inside each group of a sorted array.

    Parameters
    ----------
    starts : (g + 1,) int
        Group boundaries as returned by :func:`group_starts`.

    Returns
    -------
    pairs : (p, 2) int64
        Positions into the sorted array; ``p = sum(k * (k - 1) / 2)`` over
        group sizes ``k``.
    """
    starts = np.asarray(starts, dtype=np.int64)
    size = starts[-1]
    if size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    group_end = np.repeat(starts[1:], np.diff(starts))
    position = np.arange(size, dtype=np.int64)
    partners = group_end - position - 1          # elements after this one in its group
    first = np.repeat(position, partners)
    offset = index_in_runs(partners)
    return np.stack([first, first + 1 + offset], axis=1)


class Adjacency:
    """Compressed sparse rows of an undirected graph, for frontier expansion.

    Parameters
    ----------
    count : int
        Number of nodes.
    edges : (m, 2) int
        Each undirected edge once (both directions are stored).
    """

    def __init__(self, count, edges):
        edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        source = np.concatenate([edges[:, 0], edges[:, 1]])
        target = np.concatenate([edges[:, 1], edges[:, 0]])
        order = np.argsort(source, kind="stable")
        self.count = count
        self.target = target[order]
        self.offsets = np.zeros(count + 1, dtype=np.int64)
        np.cumsum(np.bincount(source, minlength=count), out=self.offsets[1:])

    def neighbours(self, nodes):
        """``(sources, targets)``: every edge leaving ``nodes``, as parallel arrays."""
        nodes = np.asarray(nodes, dtype=np.int64)
        begin, end = self.offsets[nodes], self.offsets[nodes + 1]
        degree = end - begin
        sources = np.repeat(nodes, degree)
        index = np.repeat(begin - np.cumsum(degree) + degree, degree) + np.arange(int(degree.sum()))
        return sources, self.target[index]

    def grow_labels(self, labels, allowed):
        """Breadth-first multi-source growth of labels.

        Parameters
        ----------
        labels : (count,) int
            ``>= 0`` on the sources, ``-1`` elsewhere.  Modified in place.
        allowed : callable ``(sources, targets) -> (k,) bool``
            Which edges labels may cross.

        Every reachable unlabelled node takes the label of the source nearest
        in hops; ties go to the smaller label.
        """
        frontier = np.flatnonzero(labels >= 0)
        unset = np.iinfo(np.int64).max
        nearest = np.full(len(labels), unset, dtype=np.int64)        # smallest label reaching each node
        slot = np.zeros(len(labels), dtype=np.int64)
        while frontier.size:
            sources, targets = self.neighbours(frontier)
            keep = (labels[targets] < 0) & allowed(sources, targets)
            targets = targets[keep]
            if not targets.size:
                break
            np.minimum.at(nearest, targets, labels[sources[keep]])
            labels[targets] = nearest[targets]
            # each reached node once (whichever of its repeats wrote its slot last)
            slot[targets] = np.arange(targets.size)
            frontier = targets[slot[targets] == np.arange(targets.size)]
        return labels


def scatter_rows(ufunc, out, index, values):
    """``ufunc.at(out, index, values)`` for rows: ``out`` (n, c), ``index`` (k,), ``values`` (k, c).

    One column at a time: numpy's ``at`` over rows takes a slow path, three
    times slower than over a column.  The same result to the bit (each column
    is still reduced in index order).  Returns ``out``.
    """
    for c in range(out.shape[1]):
        ufunc.at(out[:, c], index, values[:, c])
    return out


def put_pairs(target, index, pairs):
    """``target[index] = pairs``, each pair moved as one 8-byte item: a scatter of single items, three to four
    times faster than numpy's row by row (0.08 s against 0.02 s for 3M rows).

    Parameters
    ----------
    target : (n, 2) float32, C-contiguous, written in place
    index : (k,) int (any shape, read flat): where each pair goes; a repeated index keeps the last pair, as
        numpy's assignment does
    pairs : (k, 2) float (any shape ending in 2, read flat), rounded to float32 as the assignment rounds
    """
    if target.dtype != np.float32 or target.ndim != 2 or target.shape[1] != 2 or not target.flags.c_contiguous:
        raise ValueError("put_pairs writes into a C-contiguous (n, 2) float32 array")
    pairs = np.ascontiguousarray(np.asarray(pairs).reshape(-1, 2), dtype=np.float32)
    target.view(np.int64).reshape(-1)[np.asarray(index).ravel()] = pairs.view(np.int64).reshape(-1)


def unique_rows(pairs):
    """Sorted unique rows of a (n, 2) non-negative int array, as int64."""
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if not len(pairs):
        return pairs
    order = sort_order(pairs[:, 0], pairs[:, 1])
    pairs = pairs[order]
    keep = np.ones(len(pairs), dtype=bool)
    keep[1:] = (pairs[1:] != pairs[:-1]).any(axis=1)
    return pairs[keep]


def unique_pairs(pairs):
    """Unordered pairs, each once: ``pairs`` (n, 2) int -> (p, 2) int64 rows ``i < j`` (or ``i == j``), sorted."""
    return unique_rows(np.sort(np.asarray(pairs, dtype=np.int64).reshape(-1, 2), axis=1))
