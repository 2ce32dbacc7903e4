"""The sides of a chart's triangles, grouped by edge, from one sort per mesh.

:func:`.overlap.fold_conflicts` runs once per axis and round, and each run
needs the sides of its chart triangles grouped by (chart, edge).  Sorting them
afresh in every run took 0.7 to 0.8 s of a 1M-triangle scan's bake (nine
runs; keys led by the chart are in no order a sort can follow).
:func:`mesh_order` sorts every side by its edge once; a run keeps the sides of
its chart triangles (a mask, which keeps the order) and brings one chart's
sides of an edge together with a stable sort of keys already in order but for
an edge of three sides or more (:func:`..arrays.graph.sort_order` follows runs
already in order).
"""

from typing import NamedTuple

import numpy as np

from ..arrays.graph import index_type, sort_order


class MeshOrder(NamedTuple):
    """Every side of a mesh's triangles with two distinct ends, sorted by its welded edge, stably.

    ``tri`` (s,) int, ``corner`` (s,) int8: the triangle and the corner the side starts at; ``edge`` (s,)
    int: its edge's number, ascending; ``low``, ``high`` (s,) int: its welded ends; ``forward`` (s,) bool: it
    runs from ``low`` to ``high``.  Indices are int32 where they fit."""

    tri: np.ndarray
    corner: np.ndarray
    edge: np.ndarray
    low: np.ndarray
    high: np.ndarray
    forward: np.ndarray


def mesh_order(welded_triangles):
    """:class:`MeshOrder` of ``welded_triangles`` (t, 3) int (one sort of 3t entries)."""
    welded_triangles = np.asarray(welded_triangles)
    index = index_type(max(welded_triangles.size, int(welded_triangles.max(initial=0)) + 1))
    start = welded_triangles.astype(index).ravel()                 # int32 where it fits: half the bytes to move
    end = welded_triangles[:, [1, 2, 0]].astype(index).ravel()
    real = np.flatnonzero(start != end)
    low, high = np.minimum(start[real], end[real]), np.maximum(start[real], end[real])
    by_edge = sort_order(low, high)
    side, low, high = real[by_edge], low[by_edge], high[by_edge]
    new_edge = np.ones(len(side), dtype=bool)
    new_edge[1:] = (low[1:] != low[:-1]) | (high[1:] != high[:-1])
    return MeshOrder((side // 3).astype(index), (side % 3).astype(np.int8), np.cumsum(new_edge, dtype=index) - 1,
                     low, high, start[side] == low)


class ChartSides(NamedTuple):
    """Every side of every chart triangle, sorted so each chart's uses of one edge are a run.

    ``tri``, ``corner`` (s,) int: the triangle and its corner the side starts at; ``low``, ``high`` (s,) int: its
    welded ends; ``forward`` (s,) bool: it runs from ``low`` to ``high``; ``starts`` (r + 1,) int: where each
    run (one edge of one chart) starts; ``uses`` (r,) int: its length; ``boundary`` (b,) int: the sides used
    once (the charts' boundaries).  Runs follow their edges; a run lists its sides in triangle order."""

    tri: np.ndarray
    corner: np.ndarray
    low: np.ndarray
    high: np.ndarray
    forward: np.ndarray
    starts: np.ndarray
    uses: np.ndarray
    boundary: np.ndarray


def chart_sides(group, welded_triangles, live, order=None):
    """:class:`ChartSides` of the triangles ``live`` (``group`` (t,) their chart); zero-length sides left out.
    ``order``: :func:`mesh_order` of ``welded_triangles``, sorted here if not given."""
    order = mesh_order(welded_triangles) if order is None else order
    in_chart = np.zeros(len(group), dtype=bool)
    in_chart[live] = True
    picked = np.flatnonzero(in_chart[order.tri])
    tri, edge = order.tri[picked], order.edge[picked]
    chart = group[tri]
    together = sort_order(edge, chart)             # only an edge of 3+ sides can have its charts apart
    picked, tri, edge, chart = picked[together], tri[together], edge[together], chart[together]
    change = np.ones(len(tri), dtype=bool)
    change[1:] = (edge[1:] != edge[:-1]) | (chart[1:] != chart[:-1])
    starts = np.concatenate((np.flatnonzero(change), [len(tri)]))
    uses = np.diff(starts)
    return ChartSides(tri, order.corner[picked], order.low[picked], order.high[picked], order.forward[picked],
                      starts, uses, starts[:-1][uses == 1])
