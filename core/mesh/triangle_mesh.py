"""The mesh as the core sees it, and what is wrong with it.

A :class:`TriangleMesh` is triangles grouped into faces (Blender's polygons):
every triangle of a face must land in the same chart, because Blender stores
UVs per face corner.  All geometry is float64.
"""

from dataclasses import dataclass, field

import numpy as np

from ..arrays.graph import scatter_rows, sort_order
from ..arrays.reduce import row_length
from ..errors import SeamlessAOError
from .corner_values import CornerValues
from .extent import box_size, mesh_size, robust_box
from .weld import vertex_pieces


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
    normals_as_read: np.ndarray  # (t, 3, 3) corner normals, as read (not yet sanitised), or their CornerValues
    face_count: int = 0
    vertex_island: np.ndarray = None     # (v,) int, optional
    side_edge: np.ndarray = None         # (t, 3) int, optional
    _mesh: object = field(default=None, init=False, repr=False)

    def mesh(self):
        """The :class:`TriangleMesh` (built on first use, then kept)."""
        if self._mesh is None:
            self._mesh = TriangleMesh(self.positions, self.triangles, self.triangle_face, self.normals_as_read,
                                      face_count=self.face_count, vertex_island=self.vertex_island,
                                      side_edge=self.side_edge)
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
    normals_as_read : (t, 3, 3) float, or :class:`CornerValues` of them
        Shading normal at each triangle corner (flat faces: the face normal),
        as given: Blender's are float32, and some may be zero or not finite.
    vertex_island : (v,) int or None
        Each vertex's island where the reader knows it (the triangles joined
        through shared vertex indices, ``0 ..``: Blender's Mesh Island), for
        :attr:`vertex_piece` (:func:`.weld.vertex_pieces`' ``islands``).
    side_edge : (t, 3) int or None
        Where the reader knows it, the edge of each triangle side (from corner
        ``j`` to the next): two sides share a number exactly when they join the
        same two vertices (Blender's edges, one per pair of vertices, and a
        number for each quad's inner diagonal), for pairing sides without a
        sort (:func:`..atlas.rim.edge_twins`).
    corner_normals : (t, 3, 3) float64
        Those normals made unit (:func:`sanitized_normals`), a new array each
        use: a bake's passes take those of the triangles they need
        (:meth:`normals_of`), and the mesh keeps only the normals as read
        (36 MB a million triangles, not 72).
    scale : float
        Bounding-box diagonal of the used vertices, a few stray ones left out
        (:func:`.extent.robust_box`; the largest part's, for meshes put together
        with :meth:`concatenate`).
    box : ((3,), (3,)) float64
        That box, ``(low, high)`` (of all parts together, for meshes put together).
    stray : (t,) bool
        The triangles left out of it (a spike to a stray vertex, a few
        triangles floating far off): their charts get few texels
        (:func:`..atlas.long_charts.long_chart_factors`).
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
        corner_height)`` from the triangle's border.  A new array each use:
        a bake asks :meth:`corner_height_of` the triangles it needs.
    longest_side : (t,) float64
        Twice each triangle's area over its least ``corner_height``: its
        longest side (0 for a degenerate one), worked out at the first use
        and kept (the density estimate of a mesh laid out whole reads all of
        them; one laid out on a proxy never does).
    """

    positions: np.ndarray
    triangles: np.ndarray
    triangle_face: np.ndarray
    normals_as_read: np.ndarray
    face_count: int = 0
    vertex_island: np.ndarray = None
    side_edge: np.ndarray = None
    # Derived, filled by ``__post_init__``.
    scale: float = field(init=False, default=1.0)
    box: tuple = field(init=False, repr=False, default=None)
    stray: np.ndarray = field(init=False, repr=False, default=None)
    part_of_vertex: np.ndarray = field(init=False, repr=False, default=None)
    part_scale: np.ndarray = field(init=False, repr=False, default=None)
    _cross: np.ndarray = field(init=False, repr=False, default=None)
    _longest_side: np.ndarray = field(init=False, repr=False, default=None)
    triangle_area: np.ndarray = field(init=False, repr=False, default=None)
    triangle_normal: np.ndarray = field(init=False, repr=False, default=None)
    degenerate: np.ndarray = field(init=False, repr=False, default=None)
    _vertex_piece: np.ndarray = field(init=False, repr=False, default=None)

    def __post_init__(self):
        self.positions = np.ascontiguousarray(self.positions, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.ascontiguousarray(self.triangles, dtype=np.int64).reshape(-1, 3)
        self.triangle_face = np.ascontiguousarray(self.triangle_face, dtype=np.int64).reshape(-1)
        if isinstance(self.normals_as_read, CornerValues):                  # gathered where read
            if self.normals_as_read.shape[1:] != (3, 3):
                raise ValueError("normals_as_read must hold a 3-vector at each triangle corner")
        else:
            normals = np.asarray(self.normals_as_read)
            self.normals_as_read = np.ascontiguousarray(
                normals, dtype=normals.dtype if normals.dtype in (np.float32, np.float64) else np.float64
            ).reshape(-1, 3, 3)
        t = len(self.triangles)
        if len(self.triangle_face) != t or len(self.normals_as_read) != t:
            raise ValueError("triangles, triangle_face and normals_as_read must have the same length")
        if t and (self.triangles.min() < 0 or self.triangles.max() >= len(self.positions)):
            raise ValueError("triangle vertex index out of range")
        if self.vertex_island is not None:
            self.vertex_island = np.ascontiguousarray(self.vertex_island).reshape(-1)
            if len(self.vertex_island) != len(self.positions):
                raise ValueError("vertex_island must have one island per vertex")
        if self.side_edge is not None:
            self.side_edge = np.ascontiguousarray(self.side_edge).reshape(-1, 3)
            if len(self.side_edge) != t or (t and int(self.side_edge.min()) < 0):
                raise ValueError("side_edge must give each triangle side an edge number >= 0")
        if not np.isfinite(self.positions).all():
            raise SeamlessAOError("The mesh has vertices at infinite or undefined (NaN) positions")
        if not self.face_count:
            self.face_count = int(self.triangle_face.max()) + 1 if t else 0
        low, high, self.stray = robust_box(self.positions, self.triangles)
        self.box = (low, high)
        self.scale = box_size(low, high) if t else mesh_size(self.positions)
        self.part_of_vertex = np.zeros(len(self.positions), dtype=np.int64)
        self.part_scale = np.array([self.scale])
        self._cross = _cross_of_corners(*_corner_columns(self.positions, self.triangles))
        length = row_length(self._cross)
        self.triangle_area = 0.5 * length
        self.degenerate = self.triangle_area <= DEGENERATE_AREA * self.scale**2
        self.triangle_normal = np.zeros_like(self._cross)
        np.divide(self._cross, length[:, None], out=self.triangle_normal, where=~self.degenerate[:, None])

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
            np.concatenate([m.normals_as_read for m in meshes]),
            face_count=int(face_offsets[-1]),
            vertex_island=_concatenated_numbers([m.vertex_island for m in meshes]),
            side_edge=_concatenated_numbers([m.side_edge for m in meshes]),
        )
        # each part's normals are made unit against its own triangle normals (the same ones, concatenated)
        for name in ("triangle_cross", "triangle_area", "triangle_normal", "degenerate", "stray"):
            setattr(combined, name, np.concatenate([getattr(m, name) for m in meshes]))
        combined.scale = max(m.scale for m in meshes)
        combined.part_of_vertex = np.repeat(np.arange(len(meshes)), np.diff(vertex_offsets))
        combined.part_scale = np.array([m.scale for m in meshes], dtype=np.float64)
        return combined, np.cumsum([0] + [len(m.triangles) for m in meshes])

    corners = property(lambda self: self.positions[self.triangles], doc="(t, 3, 3) float64, a new copy each use")
    @property
    def triangle_cross(self):
        """(t, 3) float64: ``(second - first) x (third - first)`` of each triangle's corners.  Kept from the
        build until :meth:`let_go_of_cross` (the layout's charts and packing are its last readers, and
        24 bytes a triangle would last through the bake), then worked out again if asked."""
        if self._cross is None:
            self._cross = _cross_of_corners(*_corner_columns(self.positions, self.triangles))
        return self._cross

    @triangle_cross.setter
    def triangle_cross(self, value):
        self._cross = value

    def let_go_of_cross(self):
        """Free :attr:`triangle_cross` (it comes back, the same bits, if read again)."""
        self._cross = None

    @property
    def longest_side(self):
        """See the class; worked out at the first use, then kept."""
        if self._longest_side is None:
            first, second, third = _corner_columns(self.positions, self.triangles)
            # the least of the three heights is over the longest side (a division rounds monotonically: the
            # same bits)
            longest = np.maximum(np.maximum(_distance(third, second), _distance(first, third)),
                                 _distance(second, first))
            del first, second, third
            least_height = row_length(self.triangle_cross) / np.maximum(longest, 1e-300)
            self._longest_side = 2.0 * self.triangle_area / np.maximum(least_height, 1e-300)
        return self._longest_side

    @property
    def vertex_piece(self):
        """(v,) int64: the piece of every vertex (:func:`.weld.vertex_pieces`), worked out at the first use and
        kept (8 bytes a vertex): a bake's proxy layout and its sealed test both read it, and it took 0.25 s a
        million triangles each time."""
        if self._vertex_piece is None:       # meshes put together are pieces apart, whatever touches
            self._vertex_piece = vertex_pieces(self.positions, self.triangles,
                                               self.part_of_vertex if len(self.part_scale) > 1 else None,
                                               islands=self.vertex_island)
        return self._vertex_piece

    corner_height = property(lambda self: self.corner_height_of(slice(None)),
                             doc="(t, 3) float64, each triangle's heights, a new array each use")

    def corner_height_of(self, triangle):
        """(k, 3) float64: the height of each of ``triangle`` (k,) int (or a slice) over the side opposite each
        corner (0 for a degenerate triangle), worked out from the vertices (the same bits whichever triangles
        are asked for; kept, they were 24 bytes a triangle through the whole bake)."""
        corners = self.positions[self.triangles[triangle]]
        first, second, third = corners[:, 0], corners[:, 1], corners[:, 2]
        return _corner_heights(first, second, third, row_length(np.cross(second - first, third - first)))

    corner_normals = property(lambda self: self.normals_of(slice(None)),
                              doc="(t, 3, 3) float64, unit corner normals, a new array each use")

    def normals_of(self, triangle):
        """(k, 3, 3) float64: the unit corner normals of ``triangle`` (k,) int (or a slice), as
        :func:`sanitized_normals` makes them: the same bits whichever triangles are asked for."""
        return sanitized_normals(self.normals_as_read[triangle], self.triangle_normal[triangle])

    @property
    def vertex_scale(self):
        """(v,) float64: the ``scale`` of each vertex's part."""
        return self.part_scale[self.part_of_vertex]

    @property
    def triangle_scale(self):
        """(t,) float64: the ``scale`` of each triangle's part."""
        return self.part_scale[self.part_of_vertex[self.triangles[:, 0]]]

    @property
    def face_normal(self):
        """(f, 3) float64: area-weighted unit normal of each face (zero if degenerate), worked out at each use
        (clustering reads it once; 24 bytes a face kept would last through the bake).
        """
        if len(self.part_scale) == 1 and np.array_equal(self.triangle_face, np.arange(len(self.triangles))):
            # a face per triangle, in order: the sum is the triangle's own cross product, so the face's normal is
            # the triangle's (the same test of its length, the same division; + 0.0: what adding the cross
            # product to a zero makes of a -0.0)
            return self.triangle_normal + 0.0
        summed = scatter_rows(np.add, np.zeros((self.face_count, 3)), self.triangle_face, self.triangle_cross)
        face_scale = np.zeros(self.face_count)
        face_scale[self.triangle_face] = self.triangle_scale
        length = row_length(summed)
        ok = length > 2.0 * DEGENERATE_AREA * face_scale**2
        return np.divide(summed, length[:, None], out=np.zeros_like(summed), where=ok[:, None])

    @property
    def face_degenerate(self):
        """(f,) bool: faces whose triangles are all degenerate."""
        live = np.zeros(self.face_count, dtype=bool)
        live[self.triangle_face[~self.degenerate]] = True
        return ~live


def _concatenated_numbers(numbers):
    """The numbers (each (n_i, ...) int >= 0, e.g. ``vertex_island``, ``side_edge``) of meshes put together, each
    mesh's after the last one's: (sum n_i, ...) int64; None unless every mesh has them."""
    if not numbers or any(each is None for each in numbers):
        return None
    offsets = np.cumsum([0] + [int(np.max(each, initial=-1)) + 1 for each in numbers])
    return np.concatenate([np.asarray(each, dtype=np.int64) + o for each, o in zip(numbers, offsets)])


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
    length = row_length(normals)
    bad = length < 1.0e-12
    if bad.any():                                   # only the replaced rows need measuring again
        fallback = np.broadcast_to(triangle_normal[:, None, :], normals.shape)
        normals[bad] = fallback[bad]
        length[bad] = row_length(normals[bad])
        still_bad = length < 1.0e-12
        normals[still_bad] = (0.0, 0.0, 1.0)
        length[still_bad] = 1.0
    return normals / length[..., None]


def _corner_heights(first, second, third, length):
    """(k, 3) float64: height over the side opposite each corner of triangles with corners ``first``,
    ``second``, ``third`` (k, 3) and cross-product lengths ``length`` (k,); each side one (k, 3) array at a
    time (row lengths of a (k, 3, 3) stack cost more)."""
    side = np.stack([row_length(third - second), row_length(first - third), row_length(second - first)], axis=1)
    return length[:, None] / np.maximum(side, 1e-300)


def _corner_columns(positions, triangles):
    """The corners of ``triangles`` (t, 3) as three lists (first, second, third corner) of three (t,) arrays
    (x, y, z): numpy's loops over (t, 3) views run three items a row, over (t,) arrays all t at once."""
    columns = [np.ascontiguousarray(positions[:, axis]) for axis in range(3)]
    return [[column[triangles[:, corner]] for column in columns] for corner in range(3)]


def _cross_of_corners(first, second, third):
    """(t, 3) float64: ``np.cross(second - first, third - first)`` of corners given as :func:`_corner_columns`
    makes them, with numpy's arithmetic (each component ``a * b - c * d``, in that order): the same bits."""
    (ux, uy, uz), (vx, vy, vz) = ([b - a for a, b in zip(first, corner)] for corner in (second, third))
    cross = np.empty((len(ux), 3))
    cross[:, 0], cross[:, 1], cross[:, 2] = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    return cross


def _distance(a, b):
    """(t,) the lengths of ``a - b`` for points given as three (t,) arrays, :func:`row_length`'s arithmetic."""
    x, y, z = (p - q for p, q in zip(a, b))
    return np.sqrt(x * x + y * y + z * z)


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
