"""Overlapping clusters of faces along the six signed axes (thesis §7.3), made injective.

A face joins the chart of signed axis ``s`` when its normal lies within the
compare angle of ``s`` (and all its triangles face ``s``), and it is
connected to the chart through such faces.  So for each signed axis the charts
are the connected components of the faces that qualify, and a face has at most
one chart per axis: X, Y and Z.  A component becomes a chart when it holds at
least one face whose dominant (closest) signed axis is ``s``; every face
qualifies for its dominant axis whatever the angle, so every non-degenerate face
lands in at least one chart.  This is the thesis' breadth-first growth from
uncovered seeds, made independent of seed order.

Signed axes (thesis' planes were unsigned, so the front and back of a thin part
shared texels) are numbered ``0..5`` = +X, -X, +Y, -Y, +Z, -Z.

The teapot problem (thesis §9): a chart can fold over itself in projection.
:func:`make_injective` finds folds with :func:`.overlap.fold_conflicts` and
parts every conflicting pair of faces at once (:mod:`.splitting`: a graph
Voronoi split from the conflicting faces, its cells merged back where no
conflict keeps them apart), until no chart has a conflict.
"""

from dataclasses import dataclass

import numpy as np

from ..arrays.blocks import row_blocks
from ..arrays.geometry2d import group_boxes
from ..arrays.graph import Adjacency, connected_components, group_starts, index_in_runs, scatter_rows
from .overlap import FoldMemory, fold_conflicts
from .sides import mesh_order
from .splitting import part_conflicts

#: (6, 3) unit vector of each signed axis.
AXES = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
#: (6, 2, 3) chart-plane basis (u, v) of each signed axis, with u x v = axis, so
#: that looking at a face from outside its image is never mirrored.  Side charts
#: keep +Z up.
BASES = np.array([
    [[0, 1, 0], [0, 0, 1]],     # +X: u = +Y, v = +Z
    [[0, -1, 0], [0, 0, 1]],    # -X: u = -Y
    [[-1, 0, 0], [0, 0, 1]],    # +Y: u = -X
    [[1, 0, 0], [0, 0, 1]],     # -Y: u = +X
    [[1, 0, 0], [0, 1, 0]],     # +Z: u = +X, v = +Y
    [[1, 0, 0], [0, -1, 0]],    # -Z: v = -Y
], dtype=np.float64)
#: A triangle must face its chart's axis at least this much (cosine).
FRONT_FACING = 0.01
#: Overlapping triangles closer than this (relative to mesh size) in depth are one surface.
SAME_SURFACE = 1.0e-6
#: Chart boundaries closer than this (relative to mesh size) in 2D touch.
TOUCH = 1.0e-7


def project(points, signed_axis, axis=None):
    """Project points on the chart plane of their signed axis.

    Parameters
    ----------
    points : (..., 3) float64
    signed_axis : int or (...,) int, 0..5
    axis : int, optional
        The one axis (0..2) every ``signed_axis`` lies on, when the caller
        knows (a pass over one axis' charts): its columns are then read as
        they are, with no gather, for the same values.

    Returns
    -------
    uv : (..., 2) float64, object units
    depth : (...,) float64, distance along the signed axis
    """
    points = np.asarray(points, dtype=np.float64)
    shape = points.shape[:-1]
    signed_axis = np.broadcast_to(np.asarray(signed_axis), shape).ravel()
    uv = np.empty((len(signed_axis), 2))
    if axis is not None:
        columns = points.reshape(-1, 3)
        uv[:, 0] = columns[:, _U_COMPONENT[axis]] * _U_SIGN[signed_axis]
        uv[:, 1] = columns[:, _V_COMPONENT[axis]] * _V_SIGN[signed_axis]
        depth = columns[:, axis] * _DEPTH_SIGN[signed_axis]
        return uv.reshape(shape + (2,)), depth.reshape(shape)
    axis = signed_axis // 2
    # one gather per output from the flat coordinates (masking by axis costs four times as much)
    flat = points.ravel()
    base = np.arange(0, flat.size, 3)
    uv[:, 0] = flat[base + _U_COMPONENT[axis]] * _U_SIGN[signed_axis]
    uv[:, 1] = flat[base + _V_COMPONENT[axis]] * _V_SIGN[signed_axis]
    depth = flat[base + axis] * _DEPTH_SIGN[signed_axis]
    return uv.reshape(shape + (2,)), depth.reshape(shape)


def project_corners(mesh, triangles, signed_axis, axis=None):
    """The corners of some triangles on the chart planes of their signed axes, read from the vertices:
    ``project(mesh.corners[triangles], signed_axis[:, None], axis)[0]`` (the same values) without a (k, 3, 3)
    copy of every corner first (at a million triangles the copy took longer than the rest).

    A block of triangles at a time (:func:`..arrays.blocks.row_blocks`): the gathers' index temporaries stay a
    few MB (the whole (k, 3) at once allocated four of 34 MB at a million members, and fresh pages cost).

    Parameters
    ----------
    mesh : TriangleMesh
    triangles : (k,) int
    signed_axis : (k,) int, 0..5
    axis : int, optional, the one axis every ``signed_axis`` lies on, when the caller knows

    Returns
    -------
    uv : (k, 3, 2) float64, object units
    """
    triangles = np.asarray(triangles)
    signed_axis = np.broadcast_to(np.asarray(signed_axis), triangles.shape)
    flat = mesh.positions.ravel()
    uv = np.empty(triangles.shape + (3, 2))
    for block in row_blocks(len(triangles)):
        corner_at = mesh.triangles[triangles[block]] * 3                      # (b, 3) into the flat positions
        signed = signed_axis[block]
        on_axis = signed // 2 if axis is None else axis
        out = uv[block]
        out[..., 0] = flat[corner_at + np.reshape(_U_COMPONENT[on_axis], (-1, 1))] * _U_SIGN[signed][:, None]
        out[..., 1] = flat[corner_at + np.reshape(_V_COMPONENT[on_axis], (-1, 1))] * _V_SIGN[signed][:, None]
    return uv


# The same bases as BASES, as component indices and signs (for speed).
_U_COMPONENT = np.abs(BASES[::2, 0]).argmax(axis=1)
_V_COMPONENT = np.abs(BASES[::2, 1]).argmax(axis=1)
_U_SIGN = BASES[:, 0].sum(axis=1)
_V_SIGN = BASES[:, 1].sum(axis=1)
_DEPTH_SIGN = AXES.sum(axis=1)


@dataclass
class Charts:
    """Faces grouped into charts.

    Attributes
    ----------
    chart_of_face : (f, 3) int64
        Chart holding each face on axis X, Y, Z; ``-1`` if none.
    chart_axis : (c,) int64
        Signed axis (0..5) of each chart; chart ``c`` lives on axis ``chart_axis[c] // 2``.
    dominant_axis : (f,) int64
        Signed axis closest to each face's normal; ``-1`` for degenerate faces.
    splits : int
        How many chart splits the injectivity repair made.
    """

    chart_of_face: np.ndarray
    chart_axis: np.ndarray
    dominant_axis: np.ndarray
    splits: int = 0

    @property
    def count(self):
        return len(self.chart_axis)

    def faces_of_chart(self, chart):
        """(k,) int64 faces of one chart, ascending."""
        axis = int(self.chart_axis[chart]) // 2
        return np.flatnonzero(self.chart_of_face[:, axis] == chart)

    def dominant_chart(self):
        """(f,) int64: each face's chart on its dominant axis (``-1`` for degenerate faces)."""
        out = np.full(len(self.dominant_axis), -1, dtype=np.int64)
        live = self.dominant_axis >= 0
        out[live] = self.chart_of_face[live, self.dominant_axis[live] // 2]
        return out


def axis_cosines(vectors):
    """(n, 6) float64: ``vectors @ AXES.T`` for (n, 3) ``vectors`` (along +X, -X, +Y, -Y, +Z, -Z), a column at a
    time, no matrix product: numpy hands one to OpenBLAS's threads, which on 2 shared cores took 5 to 50 ms to
    wake for 125k rows (the copies take 3)."""
    vectors = np.asarray(vectors, dtype=np.float64).reshape(-1, 3)
    cosines = np.empty((len(vectors), 6))
    for axis in range(3):
        cosines[:, 2 * axis] = vectors[:, axis]
        np.negative(vectors[:, axis], out=cosines[:, 2 * axis + 1])
    return cosines


def nearest_signed_axis(vectors):
    """(n,) int64: ``np.argmax(axis_cosines(vectors), axis=1)`` (0 +X .. 5 -Z, the first of equals), no (n, 6)."""
    x, y, z = (np.abs(vectors[:, k]) for k in range(3))
    axis = np.where(z > np.maximum(x, y), 2, (y > x).astype(np.int64))
    axis[np.isnan(z)], axis[np.isnan(y)], axis[np.isnan(x)] = 2, 1, 0     # argmax's largest: the first NaN
    return 2 * axis + (np.take_along_axis(vectors, axis[:, None], axis=1)[:, 0] < 0.0)


def face_axis_cosines(mesh, face_normal):
    """Per-face cosines to the six signed axes, from ``face_normal`` (f, 3), :attr:`mesh.face_normal`.

    Returns
    -------
    face_cos : (f, 6) float64
        Cosine between each face's (area-weighted) normal and each axis.
    worst_cos : (f, 6) float64
        Smallest cosine over the face's non-degenerate triangles (a warped
        polygon may have triangles facing away from an axis its normal faces).
    """
    face_cos = axis_cosines(face_normal)
    live = ~mesh.degenerate
    worst_cos = scatter_rows(np.minimum, np.full((mesh.face_count, 6), np.inf), mesh.triangle_face[live],
                             axis_cosines(mesh.triangle_normal[live]))
    worst_cos[~np.isfinite(worst_cos)] = -1.0
    return face_cos, worst_cos


#: Rounds of averaging each face's normal with its neighbours' before clustering (:func:`smoothed_face_normals`).
NORMAL_SMOOTHING = 2


def smoothed_face_normals(mesh, edges, face_normal, rounds=NORMAL_SMOOTHING):
    """(f, 3) unit normals of each face averaged, area-weighted, with its edge neighbours ``rounds`` times.

    Parameters
    ----------
    mesh : TriangleMesh
    edges : (e, 2) int, faces sharing an edge (:attr:`..mesh.adjacency.Topology.face_edges`)
    face_normal : (f, 3) float64, :attr:`mesh.face_normal`: where the average is zero
    """
    weighted = scatter_rows(np.add, np.zeros((mesh.face_count, 3)), mesh.triangle_face, mesh.triangle_cross)
    for _ in range(rounds):
        summed = weighted.copy()
        scatter_rows(np.add, summed, edges[:, 0], weighted[edges[:, 1]])
        scatter_rows(np.add, summed, edges[:, 1], weighted[edges[:, 0]])
        weighted = summed
    length = np.linalg.norm(weighted, axis=1, keepdims=True)
    return np.divide(weighted, length, out=face_normal.copy(), where=length > 0)


def cluster_faces(mesh, topology, compare_angle=60.0):
    """Overlapping signed-axis charts, made injective (no fold in any projection).

    :func:`signed_axis_clusters` followed by :func:`make_injective`.
    """
    return make_injective(mesh, topology, signed_axis_clusters(mesh, topology, compare_angle))


def signed_axis_clusters(mesh, topology, compare_angle=60.0):
    """Overlapping signed-axis clusters (thesis §7.3 with signed axes), not yet injective.

    Parameters
    ----------
    mesh : TriangleMesh
    topology : Topology
        From :func:`..mesh.adjacency.face_adjacency`.
    compare_angle : float, degrees
        A face joins a chart of axis ``s`` when its normal is within this angle of ``s``.

    Returns
    -------
    Charts
    """
    face_normal = mesh.face_normal                      # worked out once here, kept by no one after
    face_cos, worst_cos = face_axis_cosines(mesh, face_normal)
    live = ~mesh.face_degenerate
    edges = topology.face_edges
    # Which axes a face joins follows the surface's normal around it, not each face's own (a scanner's noise
    # tilts single faces every way and would cut charts into slivers), as long as the face itself faces it.
    smooth_cos = axis_cosines(smoothed_face_normals(mesh, edges, face_normal))
    dominant = np.argmax(smooth_cos, axis=1)
    own = worst_cos[np.arange(len(dominant)), dominant] <= FRONT_FACING
    dominant = np.where(own, np.argmax(face_cos, axis=1), dominant)
    dominant = np.where(live, dominant, -1)
    face_cos = smooth_cos
    threshold = np.cos(np.radians(compare_angle))
    chart_of_face = np.full((mesh.face_count, 3), -1, dtype=np.int64)
    chart_axis = []
    for axis in range(3):
        sign_of_face = np.full(mesh.face_count, -1, dtype=np.int64)
        for signed in (2 * axis, 2 * axis + 1):
            qualifies = live & (
                ((face_cos[:, signed] >= threshold) & (worst_cos[:, signed] > FRONT_FACING))
                | (dominant == signed))
            sign_of_face[qualifies] = signed
        same = (sign_of_face[edges[:, 0]] >= 0) & (sign_of_face[edges[:, 0]] == sign_of_face[edges[:, 1]])
        component = connected_components(mesh.face_count, edges[same])
        seeded = np.zeros(mesh.face_count, dtype=bool)
        seeded[component[dominant == sign_of_face]] = True    # holds a face dominant on this sign
        member = (sign_of_face >= 0) & seeded[component]
        # Each chart is a component of member faces (a face of a component of two or more has a sign, so a
        # seeded component's faces are all members); components are numbered in order of their smallest
        # face, the first of each number along the faces.  So each chart's number and first face, unsorted.
        chart_face = component[member]
        present = np.zeros(mesh.face_count, dtype=bool)
        present[chart_face] = True
        local = (np.cumsum(present) - 1)[chart_face]
        first_of_component = np.ones(mesh.face_count, dtype=bool)
        first_of_component[1:] = component[1:] > np.maximum.accumulate(component)[:-1]
        first_face = np.flatnonzero(first_of_component)[np.flatnonzero(present)]
        chart_of_face[member, axis] = len(chart_axis) + local
        chart_axis.extend(sign_of_face[first_face].tolist())
    return Charts(chart_of_face, np.array(chart_axis, dtype=np.int64), dominant.astype(np.int64))


def triangle_chart_geometry(mesh, charts, axis, corners):
    """Triangles of the charts on one axis, projected from ``corners`` (``mesh.corners``, which a caller going
    through all three axes gathers once).

    Returns
    -------
    group : (t,) int64, chart of each triangle on this axis (``-1`` none or degenerate)
    uv : (t, 3, 2) float64, depth : (t, 3) float64, slope : (t,) float64
    """
    group = charts.chart_of_face[mesh.triangle_face, axis].copy()
    group[mesh.degenerate] = -1
    signed = np.where(group >= 0, charts.chart_axis[np.maximum(group, 0)], 2 * axis)
    uv, depth = project(corners, signed[:, None], axis)
    # the normal's component along the signed axis (AXES rows are unit axes)
    cos = np.clip(mesh.triangle_normal[:, axis] * _DEPTH_SIGN[signed], 0.05, 1.0)
    slope = np.sqrt(1.0 - cos**2) / cos
    return group, uv, depth, slope


def make_injective(mesh, topology, charts, margin=0.0, same_place=0.0):
    """Split charts until none of them folds over itself in projection.

    Parameters
    ----------
    mesh : TriangleMesh
    topology : Topology
    charts : Charts
    margin : float, object units
        Also split where two distant parts of a chart come closer than this in
        projection (see :func:`.overlap.fold_conflicts`); use about two
        texels so bilinear filtering never mixes distant surfaces.
    same_place : float, object units
        Leave alone two triangles whose centres are closer than this: one
        surface at the scale of a proxy made of cubes this wide
        (:mod:`.coarse`), whose clustering crumples it.

    Returns
    -------
    Charts, renumbered (deterministically) if anything was split.
    """
    adjacency = Adjacency(mesh.face_count, topology.face_edges)
    chart_of_face = charts.chart_of_face.copy()
    chart_axis = charts.chart_axis.copy()
    triangle_scale = mesh.triangle_scale
    corners = mesh.corners                       # (t, 3, 3): each axis projects all of them; freed on return
    order = mesh_order(topology.welded_triangles)          # every round of every axis groups sides by it
    for axis in range(3):
        dirty = None                     # charts to check; None = all of this axis
        # A split chart keeps its signed axis, so the projection is the same every round.
        _, uv, depth, slope = triangle_chart_geometry(mesh, charts, axis, corners)
        memory = FoldMemory(len(mesh.triangles))
        while True:
            group = chart_of_face[mesh.triangle_face, axis].copy()
            group[mesh.degenerate] = -1
            if dirty is not None:
                group[~dirty[np.maximum(group, 0)]] = -1
            pairs = fold_conflicts(
                uv, depth, group, topology.welded_triangles, mesh.triangle_face,
                SAME_SURFACE * triangle_scale, TOUCH * triangle_scale, margin, slope, memory=memory, order=order)
            # Two triangles of one face cannot be split apart (a face's corners hold one UV per layer): a
            # polygon folded over itself (a Boolean's n-gon, say) stays as it is rather than be split forever.
            pairs = pairs[mesh.triangle_face[pairs[:, 0]] != mesh.triangle_face[pairs[:, 1]]]
            if same_place > 0.0 and len(pairs):
                centres = corners[pairs].mean(axis=2)                          # (p, 2, 3)
                pairs = pairs[np.linalg.norm(centres[:, 0] - centres[:, 1], axis=1) >= same_place]
            if not len(pairs):
                break
            # Two triangles' faces, each pair in one chart: every pair is parted at once.
            chart_of_face[:, axis], chart_axis, split_faces = part_conflicts(
                adjacency, topology.face_edges, chart_of_face[:, axis], chart_axis, mesh.triangle_face[pairs])
            dirty = np.zeros(len(chart_axis), dtype=bool)
            dirty[chart_of_face[split_faces, axis]] = True
    result = _renumber(Charts(chart_of_face, chart_axis, charts.dominant_axis))
    result.splits = charts.splits + result.count - charts.count
    return result


def cut_long_charts(mesh, charts, max_length):
    """Cut charts longer than ``max_length`` (object units, in their plane) into slabs across their length.

    Charts are never rotated, so a chart longer than the image is wide sets
    the density of the whole layout (a 1:1000 beam would get a texel across).
    A long chart's faces are split by where their centre falls along the
    chart's longer side, into ``ceil(length / max_length)`` slabs; each slab
    with faces in it is a chart of its own on the same signed axis.  A piece of an injective
    chart is injective, so nothing else changes.

    Returns
    -------
    Charts, renumbered if anything was cut.
    """
    chart_of_face = charts.chart_of_face.copy()
    chart_axis = charts.chart_axis
    for axis in range(3):
        column = chart_of_face[:, axis]
        triangle = np.flatnonzero(column[mesh.triangle_face] >= 0)
        chart = column[mesh.triangle_face[triangle]]
        uv = project_corners(mesh, triangle, chart_axis[chart], axis)
        low, high = group_boxes(uv, chart, len(chart_axis))
        length = np.where(np.isfinite(low), high - low, 0.0)
        # slabs as a float count: a spike to a stray vertex makes its chart 10^9 slabs long, few of them used
        pieces = np.minimum(np.ceil(length.max(axis=1) / max(max_length, 1e-300)), 2.0**52)
        long_chart = pieces > 1
        keep = long_chart[chart]
        if not keep.any():
            continue
        along = np.argmax(length, axis=1)                                     # (c,) 0 = u, 1 = v
        triangle, chart, uv = triangle[keep], chart[keep], uv[keep]
        side = along[chart]                                                   # each triangle's chart's long side
        row = np.arange(len(chart))
        centre = (uv[row, 0, side] + uv[row, 1, side] + uv[row, 2, side]) / 3.0     # uv.mean(axis=1)'s sums, one side
        start, span = low[chart, along[chart]], length[chart, along[chart]]
        slab = np.clip((centre - start) / span * pieces[chart], 0, pieces[chart] - 1).astype(np.int64)
        face = mesh.triangle_face[triangle]
        # a face's slab: that of its first triangle
        face_slab = np.zeros(mesh.face_count, dtype=np.int64)
        face_slab[face[::-1]] = slab[::-1]
        faces = np.unique(face)
        old = column[faces]
        # the slabs each chart's faces are in, numbered 0, 1, ... along it; the first keeps the chart's id
        order = np.lexsort((face_slab[faces], old))
        chart_sorted, slab_sorted = old[order], face_slab[faces][order]
        piece_start = np.flatnonzero(np.r_[True, (chart_sorted[1:] != chart_sorted[:-1])
                                           | (slab_sorted[1:] != slab_sorted[:-1])])
        piece_chart = chart_sorted[piece_start]                                   # sorted: runs per chart
        chart_start = group_starts(piece_chart)
        pieces_of_chart = np.diff(chart_start)
        piece = np.empty(len(order), dtype=np.int64)
        piece[order] = np.repeat(index_in_runs(pieces_of_chart), np.diff(np.r_[piece_start, len(order)]))
        extra = np.zeros(len(chart_axis), dtype=np.int64)                         # (c,) new ids
        extra[piece_chart[chart_start[:-1]]] = pieces_of_chart - 1
        base = len(chart_axis) + np.concatenate([[0], np.cumsum(extra)])[:-1]
        column[faces] = np.where(piece == 0, old, base[old] + piece - 1)
        chart_axis = np.concatenate([chart_axis, np.repeat(chart_axis, extra)])
    if len(chart_axis) == len(charts.chart_axis):
        return charts
    return _renumber(Charts(chart_of_face, chart_axis, charts.dominant_axis, charts.splits))


def _renumber(charts):
    """Drop unused chart ids; number charts by axis, then by their smallest face."""
    used = []
    for axis in range(3):
        column = charts.chart_of_face[:, axis]           # each chart's smallest face: a scatter, not a sort
        member = np.flatnonzero(column >= 0)
        first_face = np.full(len(charts.chart_axis), len(column), dtype=np.int64)
        np.minimum.at(first_face, column[member], member)
        used.append(np.argsort(first_face, kind="stable")[:np.count_nonzero(first_face < len(column))])
    old_ids = np.concatenate(used)
    mapping = np.full(len(charts.chart_axis) + 1, -1, dtype=np.int64)
    mapping[old_ids] = np.arange(len(old_ids))
    chart_of_face = mapping[charts.chart_of_face]        # -1 maps to mapping[-1] == -1
    return Charts(chart_of_face, charts.chart_axis[old_ids], charts.dominant_axis, charts.splits)
