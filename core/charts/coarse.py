"""Charts of a mesh far finer than its image, made on a texel-scale proxy (issue 56).

On a million-triangle sculpt baked at 256², some twenty triangles share a
texel: charts, fold tests and cuts made triangle by triangle decide what no
texel can show, and cost seconds.  Here they run on a proxy instead
(:mod:`..mesh.proxy`: the vertices clustered in cubes about a texel wide, each
piece's apart, so an eye in its socket never merges with the lid), and every
face of the mesh then takes the charts of one proxy triangle:

* a face whose first triangle spans three clusters takes that triangle's
  proxy triangle, unless the clustering crumpled the proxy triangle (it
  turned more than :data:`UPRIGHT_COSINE` allows from the triangles it
  stands for: then it is dropped from the proxy);
* any other face takes, among the proxy triangles around the cluster of its
  first corner (or, with none there, its second's, then its third's), the
  one that faces most along the face's own nearest signed axis;
* a face with no proxy triangle around (a piece smaller than a cube) gets a
  chart of its own per cluster and signed axis: under a texel, the packing
  stores it as one.

The mesh's own triangles are then packed and rasterised as always, so every
texel still samples the mesh's surface.  A face lies within a cube of the
proxy triangles of its chart, so the margin the proxy's charts keep between
distant parts (:func:`.clustering.make_injective`) is widened by two cubes.
The proxy's own folds closer than :data:`SAME_PLACE_CELLS` cubes are its
clustering's crumples, not the mesh's, and split nothing.  What the proxy does
not see are folds and overlaps smaller than a cube: a scanner's noise tilting a
few triangles away inside one texel (tests/core/test_coarse.py: no two
triangles of a chart more than 1.5 texels apart overlap).
"""

import time

import numpy as np

from ..atlas.chart_atlas import expected_density
from ..atlas.long_charts import estimate_density
from ..arrays.graph import group_starts, scatter_rows, sort_order
from ..arrays.reduce import row_length
from ..mesh.adjacency import Topology, face_adjacency
from ..mesh.proxy import grid_clusters, proxy_triangles
from ..mesh.triangle_mesh import MeshArrays, MeshReport
from .clustering import (Charts, _renumber, cut_long_charts, make_injective, nearest_signed_axis,
                         signed_axis_clusters)

#: A single mesh is laid out on a proxy when it has at least this many live triangles per texel its layout is
#: expected to cover (the bake's estimate, before any chart is made).
PROXY_FROM_TRIANGLES_PER_TEXEL = 4.0
#: Side of the proxy's cubes, in texels at the density the mesh is expected to be laid out at: cubes a texel wide
#: are faster, but lose accuracy on a smooth million-triangle sculpt at 256² (the 2026-12-06 note on issue 56).
PROXY_CELL_TEXELS = 0.7
#: With at least FINE_PROXY_FROM_RAYS rays per texel the noise no longer hides what the cubes cost: cubes this many
#: texels wide, where the mesh has at least as many triangles per cube as at PROXY_FROM_TRIANGLES_PER_TEXEL with
#: PROXY_CELL_TEXELS cubes (so the proxy still has far fewer triangles than the mesh).  On the 1M-triangle Suzanne at
#: Quality Good: RMSE 0.0129, against 0.0141 with 0.7-texel cubes and 0.0135 laid out on the whole mesh; on the 1M
#: scan at Final 0.0201, against 0.0242 and 0.0238 (tests/bench/bench_proxy_cells.py).
FINE_PROXY_CELL_TEXELS = 0.5
FINE_PROXY_FROM_RAYS = 16
#: Cubes added to the margin the proxy's charts keep between distant parts (a face lies within a cube of its proxy).
MARGIN_CELLS = 2.0
#: Proxy triangles whose centres are closer than this many cubes are one surface to the fold test: the clustering
#: crumples the proxy at that scale, where the mesh itself may be smooth.
SAME_PLACE_CELLS = 3.0
#: A proxy triangle stands for its triangles only where its normal is within about 60 degrees of theirs (this
#: cosine; area-weighted): one tilted further was crumpled by the clustering, and its faces take a neighbour's.
UPRIGHT_COSINE = 0.5
#: Share of the image the layout is expected to cover (what :func:`..atlas.long_charts.estimate_density` aims at).
COVERED_SHARE = 0.55


def plane_area(mesh, compare_angle):
    """Object units²: the area the mesh's triangles would project onto the chart planes they are expected to join
    (each axis within ``compare_angle`` of the normal, and the nearest one always), what a layout lays out."""
    # a coordinate at a time: numpy sums rows of three three items at a time (the same sums, in the same order)
    cos = [np.abs(mesh.triangle_normal[:, k]) for k in range(3)]
    largest, least = np.maximum(np.maximum(cos[0], cos[1]), cos[2]), np.cos(np.radians(compare_angle))
    joined = [np.where((column >= least) | (column == largest), column, 0.0) for column in cos]
    return float((mesh.triangle_area * ((joined[0] + joined[1]) + joined[2])).sum())


def expected_texels(mesh, compare_angle, image_size=None, density=None):
    """About how many texels the mesh's charts will cover, before any is made: a ``COVERED_SHARE`` of the image,
    or at a given ``density`` (texels per object unit) its :func:`plane_area` in texels."""
    if density is not None:
        return plane_area(mesh, compare_angle) * float(density) ** 2
    return COVERED_SHARE * float(image_size) ** 2


def triangles_per_texel(mesh, compare_angle, image_size=None, density=None):
    """Live triangles of ``mesh`` per texel its layout is expected to cover (:func:`expected_texels`)."""
    live = int(np.count_nonzero(~mesh.degenerate))
    return live / max(expected_texels(mesh, compare_angle, image_size, density), 1.0)


def proxy_cell_texels(mesh, compare_angle, rays=None, image_size=None, density=None):
    """Side in texels of the cubes of the proxy ``mesh`` (one mesh, not several baked together) is laid out on
    for a bake of ``rays`` rays per texel (None: not known), or None where it is laid out whole.

    A proxy from :data:`PROXY_FROM_TRIANGLES_PER_TEXEL` live triangles per texel the layout is expected to cover
    (:func:`triangles_per_texel`, worked out once); its cubes :data:`FINE_PROXY_CELL_TEXELS` wide from
    :data:`FINE_PROXY_FROM_RAYS` rays where the mesh is that much finer still, else :data:`PROXY_CELL_TEXELS`.
    """
    per_texel = triangles_per_texel(mesh, compare_angle, image_size, density)
    if per_texel < PROXY_FROM_TRIANGLES_PER_TEXEL:
        return None
    finer = (PROXY_CELL_TEXELS / FINE_PROXY_CELL_TEXELS) ** 2
    if rays is not None and rays >= FINE_PROXY_FROM_RAYS and per_texel >= PROXY_FROM_TRIANGLES_PER_TEXEL * finer:
        return FINE_PROXY_CELL_TEXELS
    return PROXY_CELL_TEXELS


def coarse_charts(mesh, compare_angle, image_size, density, separation_texels, longest_texels, timings=None,
                  cell_texels=PROXY_CELL_TEXELS):
    """The mesh's charts, made on its texel-scale proxy (see the module).

    Parameters
    ----------
    mesh : TriangleMesh, one mesh (not several concatenated)
    compare_angle : float, degrees
    image_size : int or None; density : float or None, texels per object unit (one of them)
    separation_texels : float, what :func:`.clustering.make_injective` keeps between distant parts, in texels
    longest_texels : float: charts longer than this many texels are cut
    timings : dict, optional: gets the seconds of ``charts`` (the proxy, its charts, and the faces' charts) and
        ``injectivity`` (the proxy's charts made injective and cut), the stages the bake reports
    cell_texels : float, side of the proxy's cubes in texels (:func:`proxy_cell_texels`)

    Returns
    -------
    (Charts of the mesh's faces, Topology for the packing: the mesh's report, no face pairs: every face has a chart)
    """
    start = time.perf_counter()
    guess = float(density) if density is not None else estimate_density(
        plane_area(mesh, compare_angle), image_size, COVERED_SHARE)
    cell = cell_texels / guess
    # a piece's vertices never share a cube with another piece's: an eye in its socket stays an eye
    cluster_of_vertex, cluster_position = grid_clusters(mesh.positions, cell, mesh.vertex_piece)
    proxy, proxy_of_triangle = proxy_triangles(cluster_of_vertex, mesh.triangles)
    # a proxy triangle turned from the triangles it stands for by more than UPRIGHT_COSINE allows was crumpled
    # (or turned over) by the clustering: left out
    live = (proxy_of_triangle >= 0) & ~mesh.degenerate
    source_normal = np.zeros((len(proxy), 3))
    scatter_rows(np.add, source_normal, proxy_of_triangle[live], mesh.triangle_cross[live])
    corners = cluster_position[proxy]
    proxy_cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    upright = np.einsum("pk,pk->p", proxy_cross, source_normal) > UPRIGHT_COSINE * (
        row_length(proxy_cross) * row_length(source_normal))
    # an oriented surface runs each edge once each way: of the proxy triangles on one directed edge, the one
    # standing for the most area is kept
    upright &= one_per_directed_edge(proxy, upright, row_length(source_normal))
    renumber = np.full(len(proxy) + 1, -1, dtype=np.int64)
    renumber[np.flatnonzero(upright)] = np.arange(int(upright.sum()))
    proxy, proxy_cross = proxy[upright], proxy_cross[upright]
    proxy_of_triangle = renumber[proxy_of_triangle]
    proxy_normal = proxy_cross / np.maximum(row_length(proxy_cross)[:, None], 1e-300)
    proxy_mesh = MeshArrays(cluster_position, proxy, np.arange(len(proxy)),
                            np.repeat(proxy_normal[:, None, :], 3, axis=1), face_count=len(proxy)).mesh()

    topology = face_adjacency(proxy_mesh)
    charts = signed_axis_clusters(proxy_mesh, topology, compare_angle)
    expected = float(density) if density is not None else expected_density(proxy_mesh, charts, image_size)
    middle = time.perf_counter()
    charts = make_injective(proxy_mesh, topology, charts, margin=separation_texels / expected + MARGIN_CELLS * cell,
                            same_place=SAME_PLACE_CELLS * cell)
    charts = cut_long_charts(proxy_mesh, charts, longest_texels / expected)
    after = time.perf_counter()

    face_charts = faces_from_proxy(mesh, cluster_of_vertex, proxy, proxy_normal, proxy_of_triangle, charts)
    report = MeshReport(vertices=len(mesh.positions), triangles=len(mesh.triangles), faces=mesh.face_count,
                        degenerate_triangles=int(mesh.degenerate.sum()),
                        degenerate_faces=int(mesh.face_degenerate.sum()))
    empty = np.zeros((0, 2), dtype=np.int64)
    if timings is not None:
        timings["charts"] = (middle - start) + (time.perf_counter() - after)
        timings["injectivity"] = after - middle
    return face_charts, Topology(None, None, empty, report)


def faces_from_proxy(mesh, cluster_of_vertex, proxy, proxy_normal, proxy_of_triangle, proxy_charts):
    """Each face of ``mesh`` in the charts of one proxy triangle (see the module).

    Parameters
    ----------
    mesh : TriangleMesh
    cluster_of_vertex : (v,) int, the proxy's cluster of every vertex of ``mesh``
    proxy : (p, 3) int, the proxy's triangles (cluster indices)
    proxy_normal : (p, 3) float, their unit normals
    proxy_of_triangle : (t,) int, each triangle's proxy triangle, -1 where none stands for it
    proxy_charts : Charts of the proxy (one face per proxy triangle)

    Returns
    -------
    Charts of ``mesh``'s faces, numbered anew: the proxy's that some face took, then one per cluster and signed
    axis for faces with no proxy triangle around.
    """
    face_count = mesh.face_count
    first_triangle = np.zeros(face_count, dtype=np.int64)
    first_triangle[mesh.triangle_face[::-1]] = np.arange(len(mesh.triangles))[::-1]
    face_normal = mesh.face_normal
    live = row_length(face_normal) > 0.0
    signed = nearest_signed_axis(face_normal)
    # a proxy triangle too small to have a normal is in no chart: its faces look around instead
    proxy_live = proxy_charts.dominant_axis >= 0
    taken = proxy_of_triangle[first_triangle]
    taken[~live | ~proxy_live[np.maximum(taken, 0)]] = -1

    # around each cluster, the proxy triangle facing most along each signed axis
    cluster_count = int(cluster_of_vertex.max()) + 1 if len(cluster_of_vertex) else 0
    ring_cluster = proxy.T.ravel()
    ring_triangle = np.tile(np.arange(len(proxy)), 3)
    ring_cluster, ring_triangle = ring_cluster[proxy_live[ring_triangle]], ring_triangle[proxy_live[ring_triangle]]
    best = np.full((cluster_count, 6), -1, dtype=np.int64)
    if len(ring_cluster):
        # one stable sort by cluster; per axis, each cluster's first triangle of the highest score
        order = np.argsort(ring_cluster, kind="stable")
        ring_cluster, ring_triangle = ring_cluster[order], ring_triangle[order]
        bounds = group_starts(ring_cluster)
        start, size = bounds[:-1], np.diff(bounds)
        position = np.arange(len(order))
        for axis in range(3):
            # the score along +axis and -axis: what axis_cosines gives, a contiguous column at a time
            along = np.ascontiguousarray(proxy_normal[:, axis])[ring_triangle]
            for axis_sign, score in ((2 * axis, along), (2 * axis + 1, np.negative(along))):
                highest = np.maximum.reduceat(score, start)
                at_highest = score == np.repeat(highest, size)
                first = np.minimum.reduceat(np.where(at_highest, position, len(order)), start)
                best[ring_cluster[start], axis_sign] = ring_triangle[first]
    looking = np.flatnonzero((taken < 0) & live)
    for corner in range(3):
        found = best[cluster_of_vertex[mesh.triangles[first_triangle[looking], corner]], signed[looking]]
        taken[looking] = found
        if corner < 2:
            looking = looking[found < 0]

    chart_of_face = proxy_charts.chart_of_face[np.maximum(taken, 0)]
    dominant_axis = proxy_charts.dominant_axis[np.maximum(taken, 0)]
    chart_of_face[taken < 0] = -1
    dominant_axis[taken < 0] = -1
    chart_axis = proxy_charts.chart_axis
    # faces with no proxy triangle around: one chart per cluster (of the first corner) and signed axis
    alone = looking[taken[looking] < 0]
    if len(alone):
        key = cluster_of_vertex[mesh.triangles[first_triangle[alone], 0]] * 6 + signed[alone]
        unique_key, own = np.unique(key, return_inverse=True)
        chart_of_face[alone, signed[alone] // 2] = len(chart_axis) + own
        dominant_axis[alone] = signed[alone]
        chart_axis = np.concatenate([chart_axis, unique_key % 6])
    return _renumber(Charts(chart_of_face, chart_axis, dominant_axis))


def one_per_directed_edge(proxy, keep, weight, rounds=3):
    """(p,) bool: ``keep`` with, for every directed edge, only its heaviest kept triangle left (an oriented
    surface runs each edge once each way; of equal weights, the first triangle)."""
    keep = keep.copy()
    # each triangle's place from the heaviest: one integer key with the edge's, a sort of one key per round
    heaviest_first = np.empty(len(weight), dtype=np.int64)
    heaviest_first[np.argsort(-np.asarray(weight), kind="stable")] = np.arange(len(weight))
    for _ in range(rounds):
        index = np.flatnonzero(keep)
        key = proxy[index].ravel() * (int(proxy.max(initial=0)) + 1) + np.roll(proxy[index], -1, axis=1).ravel()
        triangle = np.repeat(index, 3)
        order = sort_order(key, heaviest_first[triangle])
        first = np.ones(len(order), dtype=bool)
        first[1:] = key[order][1:] != key[order][:-1]
        loser = triangle[order][~first]
        if not len(loser):
            break
        keep[loser] = False
    return keep
