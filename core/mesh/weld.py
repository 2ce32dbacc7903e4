"""Welding vertices: exactly equal positions (:func:`exact_weld`) and positions within a tolerance
(:func:`weld_vertices`), both by sorting, no Python loop over vertices."""

import numpy as np

from ..arrays.graph import connected_components, group_starts, scatter_rows
from ..arrays.reduce import column_max, row_any


def exact_weld(positions, groups=None, return_first=False):
    """(v,) int64: vertices at exactly the same position share an index (imported meshes split
    vertices along UV seams and hard edges; the piece is still one).

    One sort of a 64-bit hash of the coordinates' bits (a sort of rows would
    be three times slower); equal hashes of different positions, vanishingly
    rare, would only leave two vertices apart.

    Parameters
    ----------
    positions : (v, 3) float
    groups : (v,) int, optional: vertices of different groups never share an index
    return_first : bool: also return the lowest vertex of each index, (w,) int64

    Returns
    -------
    (v,) int64, numbered ``0 .. w-1`` (in no particular order)
    """
    positions = np.ascontiguousarray(np.asarray(positions, dtype=np.float64).reshape(-1, 3) + 0.0)  # -0.0 -> 0.0
    count = len(positions)
    if not count:
        empty = np.zeros(0, dtype=np.int64)
        return (empty, empty) if return_first else empty
    bits = positions.view(np.uint64)
    key = _mix(_mix(_mix(bits[:, 0]) ^ bits[:, 1]) ^ bits[:, 2])
    if groups is not None:
        groups = np.asarray(groups, dtype=np.int64)
        key = _mix(key ^ groups.astype(np.uint64))
    order = np.argsort(key)                     # hashes are in no order: numpy's unstable sort is far faster
    ordered = positions[order]
    new = np.ones(count, dtype=bool)
    new[1:] = (key[order][1:] != key[order][:-1]) | row_any(ordered[1:] != ordered[:-1])
    if groups is not None:
        new[1:] |= groups[order][1:] != groups[order][:-1]
    welded = np.empty(count, dtype=np.int64)
    welded[order] = np.cumsum(new) - 1
    if not return_first:
        return welded
    return welded, np.minimum.reduceat(order, np.flatnonzero(new))


def _mix(value):
    """A 64-bit mixing function (splitmix64's finaliser): every input bit moves every output bit, so
    coordinates whose low bits are all zero (0.5, 2.0) still hash apart."""
    value = (value ^ (value >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    value = (value ^ (value >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return value ^ (value >> np.uint64(31))


#: Weights (magnitudes adding up to one) of the direction :func:`weld_vertices` sorts along first.
_WELD_DIRECTION = np.array([0.5, 0.31, 0.19])
#: Neighbours along that direction each vertex is measured against on every axis before the grids weld it.
_WELD_WINDOW = 8


def vertex_pieces(positions, triangles, groups=None, islands=None):
    """(v,) int64: the piece of every vertex, pieces being triangles joined through corners at one position
    (:func:`exact_weld`: a box with split normals is one piece); a vertex in no triangle is a piece of its own.
    Pieces are numbered ``0 ..`` in order of each one's lowest :func:`exact_weld` index.

    Parameters
    ----------
    positions : (v, 3) float
    triangles : (t, 3) int
    groups : (v,) int, optional: vertices of different groups never join (meshes put together)
    islands : (v,) int, optional: each vertex's island, ``0 ..``, when known: the components of the triangles
        joined through corners with one vertex index (what Blender's Mesh Island node gives for a mesh without
        loose edges).  The pieces then join islands through vertices at one position, with no pass over the
        triangles (:func:`pieces_of_islands`); the same pieces, numbered the same.
    """
    if islands is not None:
        return pieces_of_islands(positions, islands, groups)
    welded = exact_weld(positions, groups)
    corner = welded[np.asarray(triangles, dtype=np.int64).reshape(-1, 3)]
    piece = connected_components(int(welded.max(initial=-1)) + 1, np.concatenate([corner[:, :2], corner[:, 1:]]))
    return piece[welded]


def pieces_of_islands(positions, islands, groups=None):
    """(v,) int64: :func:`vertex_pieces` from each vertex's island (v,) int, ``0 ..``: islands join where a
    vertex of one is at the position of a vertex of another (and of the same group, if ``groups``).

    Joining islands is a graph of islands, far fewer than vertices (a 1M-triangle sculpt has a handful); the
    pieces are then numbered as :func:`vertex_pieces` numbers those it finds from the triangles.
    """
    islands = np.asarray(islands, dtype=np.int64).reshape(-1)
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    if len(islands) != len(positions):
        raise ValueError("islands must give one island per vertex")
    if not len(islands):
        return np.zeros(0, dtype=np.int64)
    if islands.min() < 0:
        raise ValueError("islands must be numbered from 0")
    welded, first = exact_weld(positions, groups, return_first=True)
    island_count = int(islands.max()) + 1
    # each vertex joins its island to the island of the first vertex at its position
    joined = connected_components(island_count, np.stack([islands, islands[first[welded]]], axis=1))
    piece = joined[islands]
    # numbered in order of each piece's lowest welded index, as the components of the welded vertices are
    lowest = np.full(int(piece.max()) + 1, len(positions), dtype=np.int64)
    np.minimum.at(lowest, piece, welded)
    present = lowest < len(positions)
    rank = np.full(len(lowest), -1, dtype=np.int64)
    rank[np.flatnonzero(present)[np.argsort(lowest[present], kind="stable")]] = np.arange(int(present.sum()))
    return rank[piece]


def weld_vertices(positions, tolerance, groups=None):
    """Merge vertices closer than about ``tolerance`` (union over shifted grids).

    Parameters
    ----------
    positions : (v, 3) float64
    tolerance : float or (v,) float, object units (> 0)
        One tolerance, or each vertex's (the same within a group).
    groups : (v,) int, optional
        Vertices of different groups never weld (meshes put together).

    Returns
    -------
    welded : (v,) int64
        New index of every vertex, ``0 .. w-1``, in order of first occurrence
        (deterministic).  Two vertices of one group within ``tolerance / 2`` on
        every axis always weld; chains of close vertices weld transitively.
    """
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    count = len(positions)
    if count == 0:
        return np.zeros(0, dtype=np.int64)
    if groups is None:
        groups = np.zeros(count, dtype=np.int64)
    groups = np.asarray(groups, dtype=np.int64)
    group_count = int(groups.max()) + 1
    group_low = scatter_rows(np.minimum, np.full((group_count, 3), np.inf), groups, positions)
    cell = (positions - group_low[groups]) / np.broadcast_to(np.asarray(tolerance, dtype=np.float64), (count,))[:, None]
    # a stray vertex 10^9 mesh sizes out: its cell would not fit an int64, and it welds only where equal
    far = (cell > 2.0**50).any(axis=1)
    if far.any():
        cell = np.minimum(cell, 2.0**50)
    cells_per_axis = np.floor(column_max(cell)).astype(np.int64) + 2
    single_key = float(np.prod(cells_per_axis.astype(np.float64))) * group_count < 2.0**62
    # Vertices at one position share every cell: weld them at once, and only their lowest one to others.
    same, lowest = exact_weld(positions, groups, return_first=True)
    edges = [np.stack([np.arange(count), lowest[same]], axis=1)]
    lowest = np.sort(lowest)
    # Two vertices share a cell of some shifted grid only if they lie less than a cell apart on every
    # axis, so less than one apart along any direction whose weights' magnitudes add up to one (an oblique
    # one: flat walls and floors share x, y or z).  Along it, each vertex is measured against those within
    # one cell, up to _WELD_WINDOW of them each side: one that is a cell or more from all of them on some
    # axis is alone in every cell and welds with nothing (most vertices of most meshes: a 1M-triangle
    # sculpt has a vertex or two within a cell along that line, nearly never one within a cell on every axis).
    along = cell[lowest] @ _WELD_DIRECTION
    reach = 1.0 + 1e-12 * float(np.abs(cell[lowest]).max(initial=0.0))     # and what rounding may add
    lowest_group = groups[lowest]
    by_along = np.lexsort((along, lowest_group))
    sorted_group, sorted_along = lowest_group[by_along], along[by_along]
    sorted_cell = cell[lowest[by_along]].T                          # (3, w): one row per axis
    near = np.zeros(len(by_along), dtype=bool)
    for step in range(1, _WELD_WINDOW + 2):
        pair = np.flatnonzero((sorted_along[step:] - sorted_along[:-step] < reach)
                              & (sorted_group[step:] == sorted_group[:-step]))
        if not len(pair):
            break
        if step <= _WELD_WINDOW:       # within a cell on every axis: it may share one
            gap = np.abs(sorted_cell[:, pair + step] - sorted_cell[:, pair])
            pair = pair[(gap[0] < reach) & (gap[1] < reach) & (gap[2] < reach)]
        # past the window: vertices with more than _WELD_WINDOW within a cell along the line are not
        # measured against all of them, so they are left to the grids
        near[pair] = True
        near[pair + step] = True
    lonely = np.ones(count, dtype=bool)
    lonely[lowest[by_along[near]]] = False
    lonely |= far
    others = lowest[~lonely[lowest]]                   # ascending: each cell's first is still its lowest
    cell, groups = cell[others], groups[others]
    for shift in np.ndindex(2, 2, 2) if len(others) else ():
        index = np.floor(cell + 0.5 * np.asarray(shift)).astype(np.int64)
        if single_key:
            keys = ((groups * cells_per_axis[0] + index[:, 0]) * cells_per_axis[1] + index[:, 1]) \
                * cells_per_axis[2] + index[:, 2]
            order = np.argsort(keys, kind="stable")
            starts = group_starts(keys[order])
        else:                      # far-flung vertices: sort the group and cell indices instead
            rows_to_sort = np.column_stack([groups, index])
            order = np.lexsort(rows_to_sort.T[::-1])
            rows = rows_to_sort[order]
            change = np.flatnonzero((rows[1:] != rows[:-1]).any(axis=1)) + 1
            starts = np.concatenate(([0], change, [len(others)]))
        first = np.repeat(order[starts[:-1]], np.diff(starts))
        edges.append(others[np.stack([first, order], axis=1)[first != order]])
    # components come numbered in order of their smallest vertex: of first occurrence
    return connected_components(count, np.concatenate(edges))
