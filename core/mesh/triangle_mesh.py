"""The mesh as the core sees it, and what is wrong with it.

A :class:`TriangleMesh` is triangles grouped into faces (Blender's polygons):
every triangle of a face must land in the same chart, because Blender stores
UVs per face corner.  All geometry is float64.
"""

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..arrays.graph import connected_components, group_starts, scatter_rows, sort_order
from ..errors import SeamlessAOError
from .extent import box_size, mesh_size, robust_box


#: Triangles with less area than this times the squared mesh size are degenerate.
DEGENERATE_AREA = 1.0e-20
#: Vertices closer than this times the mesh size are welded for adjacency.
WELD_TOLERANCE = 1.0e-6


@dataclass
class MeshArrays:
    """A mesh as Blender gives it, before :class:`TriangleMesh` works anything out from it: what the window's
    Blender reads and hands to a background bake, which builds the :class:`TriangleMesh` itself (building it
    in the window froze it for 0.2 s at 250k triangles).  Fields as :class:`TriangleMesh`'s, any dtype."""

    positions: np.ndarray        # (v, 3)
    triangles: np.ndarray        # (t, 3)
    triangle_face: np.ndarray    # (t,)
    corner_normals: np.ndarray   # (t, 3, 3), as read (not yet sanitised)
    face_count: int = 0
    _mesh: object = field(default=None, init=False, repr=False)

    def mesh(self):
        """The :class:`TriangleMesh` (built on first use, then kept)."""
        if self._mesh is None:
            self._mesh = TriangleMesh(self.positions, self.triangles, self.triangle_face, self.corner_normals,
                                      face_count=self.face_count)
        return self._mesh


@dataclass
class TriangleMesh:
    """Triangulated mesh in a float64 working space.

    Attributes
    ----------
    positions : (v, 3) float64
        Vertex positions.
    triangles : (t, 3) int64
        Vertex indices of each triangle, counter-clockwise seen from its front.
    triangle_face : (t,) int64
        Face (polygon) of each triangle; faces are numbered ``0 .. f-1``.
    corner_normals : (t, 3, 3) float64
        Shading normal at each triangle corner (flat faces: the face normal).
    scale : float
        Bounding-box diagonal of the used vertices, a few stray ones left out
        (:func:`.extent.robust_box`; the largest part's, for meshes put together
        with :meth:`concatenate`).
    box : ((3,), (3,)) float64
        That box, ``(low, high)`` (of all parts together, for meshes put together).
    stray : (t,) bool
        The triangles left out of it (a spike to a stray vertex, a few
        triangles floating far off): their charts get few texels
        (:func:`..atlas.chart_atlas.long_chart_factors`).
    part_of_vertex : (v,) int64
        Input mesh of each vertex (all 0 for one mesh); parts never weld.
    part_scale : (p,) float64
        Each part's own ``scale``: its tolerances (welding, degenerate
        triangles, injectivity, rim inset) are relative to it.
    corners : (t, 3, 3) float64
        ``positions[triangles]``, a new copy each use (72 MB a million
        triangles: a bake's passes read the vertices instead).
    corner_height : (t, 3) float64
        Each triangle's height over the side opposite each corner (0 for a
        degenerate triangle): a point at barycentrics ``b`` is ``min(b *
        corner_height)`` from the triangle's border.
    """

    positions: np.ndarray
    triangles: np.ndarray
    triangle_face: np.ndarray
    corner_normals: np.ndarray
    face_count: int = 0
    # Derived, filled by ``__post_init__``.
    scale: float = field(init=False, default=1.0)
    box: tuple = field(init=False, repr=False, default=None)
    stray: np.ndarray = field(init=False, repr=False, default=None)
    part_of_vertex: np.ndarray = field(init=False, repr=False, default=None)
    part_scale: np.ndarray = field(init=False, repr=False, default=None)
    triangle_cross: np.ndarray = field(init=False, repr=False, default=None)
    triangle_area: np.ndarray = field(init=False, repr=False, default=None)
    triangle_normal: np.ndarray = field(init=False, repr=False, default=None)
    degenerate: np.ndarray = field(init=False, repr=False, default=None)
    corner_height: np.ndarray = field(init=False, repr=False, default=None)

    def __post_init__(self):
        self.positions = np.ascontiguousarray(self.positions, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.ascontiguousarray(self.triangles, dtype=np.int64).reshape(-1, 3)
        self.triangle_face = np.ascontiguousarray(self.triangle_face, dtype=np.int64).reshape(-1)
        self.corner_normals = np.ascontiguousarray(self.corner_normals, dtype=np.float64).reshape(-1, 3, 3)
        t = len(self.triangles)
        if len(self.triangle_face) != t or len(self.corner_normals) != t:
            raise ValueError("triangles, triangle_face and corner_normals must have the same length")
        if t and (self.triangles.min() < 0 or self.triangles.max() >= len(self.positions)):
            raise ValueError("triangle vertex index out of range")
        if not np.isfinite(self.positions).all():
            raise SeamlessAOError("The mesh has vertices at infinite or undefined (NaN) positions")
        if not self.face_count:
            self.face_count = int(self.triangle_face.max()) + 1 if t else 0
        low, high, self.stray = robust_box(self.positions, self.triangles)
        self.box = (low, high)
        self.scale = box_size(low, high) if t else mesh_size(self.positions)
        self.part_of_vertex = np.zeros(len(self.positions), dtype=np.int64)
        self.part_scale = np.array([self.scale])
        corners = self.positions[self.triangles]
        first, second, third = corners[:, 0], corners[:, 1], corners[:, 2]
        self.triangle_cross = np.cross(second - first, third - first)
        length = _row_length(self.triangle_cross)
        self.triangle_area = 0.5 * length
        # each corner's opposite side, one (t, 3) array at a time (row lengths of a (t, 3, 3) stack cost more)
        side = np.stack([_row_length(third - second), _row_length(first - third), _row_length(second - first)], axis=1)
        self.corner_height = length[:, None] / np.maximum(side, 1e-300)
        self.degenerate = self.triangle_area <= DEGENERATE_AREA * self.scale**2
        self.triangle_normal = np.zeros_like(self.triangle_cross)
        np.divide(self.triangle_cross, length[:, None], out=self.triangle_normal, where=~self.degenerate[:, None])
        self.corner_normals = sanitized_normals(self.corner_normals, self.triangle_normal)

    @classmethod
    def from_triangles(cls, positions, triangles, smooth=False):
        """One face per triangle; flat normals, or area-weighted vertex normals if ``smooth``."""
        positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
        triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        corners = positions[triangles]
        cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        if smooth:
            vertex_normal = np.zeros_like(positions)
            for k in range(3):
                np.add.at(vertex_normal, triangles[:, k], cross)
            normals = vertex_normal[triangles]
        else:
            normals = np.repeat(cross[:, None, :], 3, axis=1)
        return cls(positions, triangles, np.arange(len(triangles)), normals)

    @classmethod
    def concatenate(cls, meshes):
        """One mesh holding several, each keeping its own tolerances (degenerate test, normals).

        Returns ``(mesh, triangle_offsets)`` where part ``i`` owns triangles
        ``triangle_offsets[i]:triangle_offsets[i + 1]``.
        """
        vertex_offsets = np.cumsum([0] + [len(m.positions) for m in meshes])
        face_offsets = np.cumsum([0] + [m.face_count for m in meshes])
        combined = cls(
            np.concatenate([m.positions for m in meshes]),
            np.concatenate([m.triangles + o for m, o in zip(meshes, vertex_offsets)]),
            np.concatenate([m.triangle_face + o for m, o in zip(meshes, face_offsets)]),
            np.concatenate([m.corner_normals for m in meshes]),
            face_count=int(face_offsets[-1]),
        )
        for name in ("triangle_cross", "triangle_area", "triangle_normal", "degenerate", "corner_normals", "stray"):
            setattr(combined, name, np.concatenate([getattr(m, name) for m in meshes]))
        combined.scale = max(m.scale for m in meshes)
        combined.part_of_vertex = np.repeat(np.arange(len(meshes)), np.diff(vertex_offsets))
        combined.part_scale = np.array([m.scale for m in meshes], dtype=np.float64)
        return combined, np.cumsum([0] + [len(m.triangles) for m in meshes])

    corners = property(lambda self: self.positions[self.triangles], doc="(t, 3, 3) float64, a new copy each use")

    @property
    def vertex_scale(self):
        """(v,) float64: the ``scale`` of each vertex's part."""
        return self.part_scale[self.part_of_vertex]

    @property
    def triangle_scale(self):
        """(t,) float64: the ``scale`` of each triangle's part."""
        return self.part_scale[self.part_of_vertex[self.triangles[:, 0]]]

    @cached_property
    def face_normal(self):
        """(f, 3) float64, read-only: area-weighted unit normal of each face (zero if degenerate).

        Worked out on first use and kept (clustering reads it twice per bake).
        """
        summed = scatter_rows(np.add, np.zeros((self.face_count, 3)), self.triangle_face, self.triangle_cross)
        length = np.linalg.norm(summed, axis=1)
        out = np.zeros_like(summed)
        face_scale = np.zeros(self.face_count)
        face_scale[self.triangle_face] = self.triangle_scale
        ok = length > 2.0 * DEGENERATE_AREA * face_scale**2
        out[ok] = summed[ok] / length[ok, None]
        out.setflags(write=False)
        return out

    @property
    def face_degenerate(self):
        """(f,) bool: faces whose triangles are all degenerate."""
        live = np.zeros(self.face_count, dtype=bool)
        live[self.triangle_face[~self.degenerate]] = True
        return ~live


def boxes_near(low, high, lows, highs, reach):
    """(k,) bool: which boxes ``lows``, ``highs`` (k, 3) come within ``reach`` of the box ``low``..``high`` (3,)
    (the shortest distance between the boxes, zero where they overlap)."""
    gap = np.maximum(0.0, np.maximum(np.asarray(lows) - high, low - np.asarray(highs)))
    return np.linalg.norm(gap, axis=1) <= reach


def flattened(linear):
    """Whether a linear map (3, 3) squashes space flat: its smallest singular value is under 1e-9 of its
    largest (an object scaled to zero along an axis)."""
    singular = np.linalg.svd(np.asarray(linear, dtype=np.float64), compute_uv=False)
    return not singular[-1] > 1e-9 * singular[0]


def sanitized_normals(corner_normals, triangle_normal):
    """Unit corner normals; zero, NaN or infinite ones replaced by the triangle's normal.

    Parameters
    ----------
    corner_normals : (t, 3, 3) float
    triangle_normal : (t, 3) float, unit or zero (degenerate triangles)

    Returns
    -------
    (t, 3, 3) float64, every row unit length ((0, 0, 1) when nothing better exists).
    """
    normals = np.array(corner_normals, dtype=np.float64)
    finite = np.isfinite(normals)
    if not finite.all():
        normals[~finite.all(axis=2)] = 0.0
    length = _row_length(normals)
    bad = length < 1.0e-12
    if bad.any():                                   # only the replaced rows need measuring again
        fallback = np.broadcast_to(triangle_normal[:, None, :], normals.shape)
        normals[bad] = fallback[bad]
        length[bad] = _row_length(normals[bad])
        still_bad = length < 1.0e-12
        normals[still_bad] = (0.0, 0.0, 1.0)
        length[still_bad] = 1.0
    return normals / length[..., None]


def _row_length(vectors):
    """(...,) Euclidean length of ``vectors`` (..., 3): ``np.linalg.norm(vectors, axis=-1)``'s arithmetic
    (the squares summed in order), without its reduction over a trailing axis of 3, three times slower."""
    x, y, z = vectors[..., 0], vectors[..., 1], vectors[..., 2]
    return np.sqrt(x * x + y * y + z * z)


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
    new[1:] = (key[order][1:] != key[order][:-1]) | (ordered[1:] != ordered[:-1]).any(axis=1)
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
    cells_per_axis = np.floor(cell.max(axis=0)).astype(np.int64) + 2
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


@dataclass
class MeshReport:
    """What the core found in the input mesh; every count is also handled."""

    vertices: int = 0
    welded_vertices: int = 0
    loose_vertices: int = 0
    triangles: int = 0
    faces: int = 0
    degenerate_triangles: int = 0
    degenerate_faces: int = 0
    duplicate_triangles: int = 0
    non_manifold_edges: int = 0
    boundary_edges: int = 0
    isolated_faces: int = 0

    def problems(self):
        """Human-readable list of the non-zero problem counts."""
        names = (
            ("loose_vertices", "loose vertices"),
            ("degenerate_triangles", "zero-area triangles"),
            ("duplicate_triangles", "duplicate triangles"),
            ("non_manifold_edges", "non-manifold edges"),
            ("isolated_faces", "isolated faces"),
        )
        return ["{} {}".format(getattr(self, key), text) for key, text in names if getattr(self, key)]


def duplicate_triangle_count(welded_triangles):
    """Triangles whose welded vertex set repeats an earlier triangle's (either winding)."""
    triangles = np.asarray(welded_triangles, dtype=np.int64).reshape(-1, 3)
    if not len(triangles):
        return 0
    a, b, c = triangles.T
    low, high = np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)
    middle = a + b + c - low - high
    order = sort_order(low, middle, high)             # one folded int64 key where the ranges allow
    low, middle, high = low[order], middle[order], high[order]
    return int(((low[1:] == low[:-1]) & (middle[1:] == middle[:-1]) & (high[1:] == high[:-1])).sum())


def require_faces(mesh):
    """Raise a clear error for a mesh that has nothing to bake."""
    if not len(mesh.triangles):
        raise SeamlessAOError("The mesh has no faces to bake (only vertices or loose edges)")
    if mesh.degenerate.all():
        if (mesh.triangle_area > 0.0).any():
            raise SeamlessAOError(
                "Every face of the mesh is too small to bake next to its size ({:.3g} across): many vertices lie "
                "far from the rest; delete them, or bake the parts separately".format(mesh.scale))
        raise SeamlessAOError("Every face of the mesh has zero area; there is no surface to bake")
