"""Which faces share an edge: O(n log n) by sorting edge keys (thesis §7.2 was O(n²))."""

from dataclasses import dataclass

import numpy as np

from ..arrays.graph import group_starts, pairs_within_groups, sort_order, unique_rows
from .triangle_mesh import WELD_TOLERANCE, MeshReport, duplicate_triangle_count
from .weld import weld_vertices


@dataclass
class Topology:
    """Adjacency of a :class:`~.triangle_mesh.TriangleMesh` after welding.

    Attributes
    ----------
    welded : (v,) int64
        Welded index of every vertex.
    welded_triangles : (t, 3) int64
        Triangles in welded vertex indices.
    face_edges : (e, 2) int64
        Pairs of distinct faces sharing at least one edge, each pair once,
        smaller face first, sorted.
    report : MeshReport
    """

    welded: np.ndarray
    welded_triangles: np.ndarray
    face_edges: np.ndarray
    report: MeshReport


def edge_keys(welded_triangles, vertex_count):
    """Undirected edge key of every triangle side.

    Parameters
    ----------
    welded_triangles : (t, 3) int
    vertex_count : int

    Returns
    -------
    keys : (3t,) int64
        ``low * vertex_count + high`` for side ``k`` of triangle ``i`` at
        ``3 i + k``; ``-1`` for a zero-length side (both ends welded together).
    """
    a = welded_triangles
    b = np.roll(welded_triangles, -1, axis=1)
    low, high = np.minimum(a, b).ravel(), np.maximum(a, b).ravel()
    keys = low * np.int64(vertex_count) + high
    keys[low == high] = -1
    return keys


def face_adjacency(mesh, weld_tolerance=WELD_TOLERANCE):
    """Weld vertices by position, then pair faces that share an edge.

    Parameters
    ----------
    mesh : TriangleMesh
    weld_tolerance : float
        Relative to each part's ``scale`` (bounding-box diagonal); parts of a
        :meth:`~.triangle_mesh.TriangleMesh.concatenate`'d mesh never weld together.

    Returns
    -------
    Topology
        Non-manifold edges (3+ faces) connect every pair of their faces;
        zero-length sides and a face's own inner diagonals are ignored.
    """
    welded = weld_vertices(mesh.positions, weld_tolerance * mesh.vertex_scale, groups=mesh.part_of_vertex)
    welded_count = int(welded.max()) + 1 if len(welded) else 0
    welded_triangles = welded[mesh.triangles]
    keys = edge_keys(welded_triangles, max(welded_count, 1))
    side_triangle = np.repeat(np.arange(len(mesh.triangles), dtype=np.int64), 3)
    valid = keys >= 0
    keys, side_triangle = keys[valid], side_triangle[valid]
    # entries with equal keys are the same side of the same face: their order cannot matter
    order = sort_order(keys, mesh.triangle_face[side_triangle], stable=False)
    keys, side_face = keys[order], mesh.triangle_face[side_triangle[order]]
    sides_per_edge = np.diff(group_starts(keys))

    # Collapse each edge to its distinct faces first (a face's inner diagonal
    # lists the same face twice and is not a link between faces).
    distinct = np.ones(len(keys), dtype=bool)
    distinct[1:] = (keys[1:] != keys[:-1]) | (side_face[1:] != side_face[:-1])
    edge_key, edge_face = keys[distinct], side_face[distinct]
    starts = group_starts(edge_key)
    faces_per_edge = np.diff(starts)
    pairs = pairs_within_groups(starts)
    face_pairs = np.sort(edge_face[pairs], axis=1)
    face_edges = unique_rows(face_pairs)

    used = np.zeros(len(mesh.positions), dtype=bool)
    used[mesh.triangles.ravel()] = True
    linked = np.zeros(mesh.face_count, dtype=bool)
    linked[face_edges.ravel()] = True
    report = MeshReport(
        vertices=len(mesh.positions),
        welded_vertices=int(np.count_nonzero(np.bincount(welded[used], minlength=1))),
        loose_vertices=int((~used).sum()),
        triangles=len(mesh.triangles),
        faces=mesh.face_count,
        degenerate_triangles=int(mesh.degenerate.sum()),
        degenerate_faces=int(mesh.face_degenerate.sum()),
        duplicate_triangles=duplicate_triangle_count(welded_triangles[~mesh.degenerate]),
        non_manifold_edges=int((faces_per_edge > 2).sum()),
        boundary_edges=int((sides_per_edge == 1).sum()),
        isolated_faces=int((~linked & ~mesh.face_degenerate).sum()) if mesh.face_count > 1 else 0,
    )
    return Topology(welded, welded_triangles, face_edges, report)


