"""The rays of one baked mesh: their parameters, the space they are cast in, and the caster that casts them.

Everything here is the bpy-free half of a bake's ray setup; the Blender side
only reads scene occluders and makes its Geometry Nodes caster
(``operators/adapters/casters.py``).

A *caster* is a :class:`RayCaster`, which also declares what a caster may do
beyond casting single rays:
``cast(origins (n, 3), directions (n, 3), max_distance) -> (distance (n,), facing (n,), sealed (n,))``,
``distance`` ``inf`` for a miss, ``facing`` the dot product of the hit face's
normal with the ray (> 0: the ray hit a back face), ``sealed`` whether the hit
face belongs to a (nearly) closed piece (:mod:`..mesh.sealed`); and ``free()``.
:class:`BVHCaster` loops over ``mathutils.bvhtree.BVHTree.ray_cast``.
"""

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..arrays.reduce import column_max, column_min
from ..mesh.extent import mesh_size
from ..mesh.sealed import sealed_triangles

#: Ray origins are lifted this far (times the object size) off the surface.
ORIGIN_OFFSET = 1.0e-5


@dataclass
class AOParams:
    """Ray settings in ray space (see :func:`ray_space`)."""

    rays: int = 64
    max_distance: float = 1.0
    cone_angle: float = 90.0
    falloff: str = "NONE"
    distribution: str = "COSINE"
    ignore_backfaces: bool = False
    horizon_bias: float = 0.0
    adaptive: bool = True
    seed: int = 0
    offset: float = 1.0e-5
    ground_height: float = None

    @property
    def pilot_rays(self):
        """Rays cast for every texel before the adaptive decision (a stratified prefix of the sequence)."""
        return adaptive_pilot_rays(self.rays, self.adaptive)


def adaptive_pilot_rays(rays, adaptive):
    """Rays cast for every texel before the adaptive decision: a quarter, at least 16 (a stratified prefix)."""
    return rays if not adaptive else min(rays, max(16, rays // 4))


def ao_params(settings, positions, rays=None, rest=None):
    """:class:`AOParams` of a bake for an object whose vertices in ray space are ``positions`` (v, 3).

    The object's size (bounding-box diagonal) sets the automatic maximum
    distance (half of it) and the origin offset; the ground plane lies at
    the lowest vertex.  With ``rest`` (k, 3), the vertices without debris far
    out (:func:`rest_vertices`), both follow those: a spike to a stray vertex
    neither lengthens every ray nor drops the ground to its tip.
    ``settings`` is a :class:`..settings.BakeSettings`; ``rays`` overrides
    its ray count.
    """
    rest = positions if rest is None or not len(rest) else rest
    size = mesh_size(rest)
    return AOParams(
        rays=settings.rays if rays is None else rays,
        max_distance=0.5 * size if settings.auto_distance else settings.max_distance,
        cone_angle=settings.cone_angle, falloff=settings.falloff, distribution=settings.distribution,
        ignore_backfaces=settings.ignore_backfaces, horizon_bias=settings.horizon_bias,
        adaptive=settings.adaptive, seed=settings.seed, offset=ORIGIN_OFFSET * size,
        ground_height=float(np.min(rest[:, 2])) if settings.use_ground_plane else None)


def rest_vertices(mesh):
    """(k,) int64: the vertices of ``mesh`` its triangles use, but for debris far out (the triangles
    :attr:`..mesh.triangle_mesh.TriangleMesh.stray` marks; loose vertices are no part of the mesh), or None when the
    whole mesh is the rest (its box is :attr:`..mesh.triangle_mesh.TriangleMesh.box`)."""
    whole = (column_min(mesh.positions), column_max(mesh.positions))
    if np.array_equal(np.array(mesh.box), np.array(whole)):
        return None
    return np.unique(mesh.triangles[~mesh.stray])


class RayCaster:
    """What casts a bake's rays; every caster derives from it (:class:`BVHCaster`, the Blender side's Geometry
    Nodes and Cycles casters).  What a caster may do beyond :meth:`cast` is declared here, with what a caster
    that cannot do it answers.

    Attributes
    ----------
    name : str, the caster's ``ray_caster`` setting (``core/settings.py``'s ``CASTER_ITEMS``): settings, class
        and the report's words (:func:`..settings.caster_words`) go by it
    bakes_whole_texels : bool, whether :meth:`ambient_occlusion` computes whole texels (Cycles' AO bake);
        :class:`.job.AOJob` then hands it every ray after each texel's pilot
    warnings : list of str, what the caster has to tell the user (the Cycles caster: the GPU it was asked
        for was not there)
    """

    name = ""
    bakes_whole_texels = False
    warnings = ()

    @property
    def pilot_name(self):
        """The caster that casts each texel's first rays where this one bakes whole texels (itself if not)."""
        return self.name

    def cast(self, origins, directions, max_distance):
        """``origins``, ``directions`` (n, 3) float64 -> ``distance`` (n,), ``facing`` (n,), ``sealed`` (n,) bool."""
        raise NotImplementedError

    def ambient_occlusion(self, points, normals, geometric, samples, params):
        """The open fraction (k,) of ``samples`` rays at each point (k, 3), where :attr:`bakes_whole_texels`."""
        raise NotImplementedError("the {} caster casts single rays only".format(self.name))

    def casting_done(self):
        """No more :meth:`cast` calls are coming, only :meth:`ambient_occlusion` ones: a caster may let go of
        what casting single rays needs (:class:`.job.AOJob` says so once its pilot and creases are cast)."""

    def free(self):
        """Let go of what the caster holds (safe to call twice)."""


class BVHCaster(RayCaster):
    """Ray caster over ``mathutils.bvhtree.BVHTree`` (a Python loop: about 0.5-0.8 M rays/s per core).

    Parameters
    ----------
    positions : (v, 3) float
    triangles : (t, 3) int
    sealed : (t,) bool, optional, triangles of closed pieces (:mod:`..mesh.sealed`; none if not given)
    """

    name = "PYTHON_BVH"

    def __init__(self, positions, triangles, sealed=None):
        from mathutils.bvhtree import BVHTree

        positions = np.asarray(positions, dtype=np.float64)
        triangles = np.asarray(triangles, dtype=np.int64)
        self.tree = BVHTree.FromPolygons(positions.tolist(), triangles.tolist(), all_triangles=True)
        self.sealed = np.zeros(len(triangles), dtype=bool) if sealed is None else np.asarray(sealed, dtype=bool)

    @classmethod
    def of_tree(cls, tree, sealed):
        """A caster over a ``mathutils.bvhtree.BVHTree`` built elsewhere (the Blender side builds one from an
        object), whose hits' indices are into ``sealed`` (n,) bool."""
        caster = cls.__new__(cls)
        caster.tree, caster.sealed = tree, np.asarray(sealed, dtype=bool)
        return caster

    def cast(self, origins, directions, max_distance):
        from mathutils import Vector

        count = len(origins)
        distance = np.full(count, np.inf)
        facing = np.zeros(count)
        hit_face = np.full(count, -1, dtype=np.int64)
        ray_cast = self.tree.ray_cast
        for i, (origin, direction) in enumerate(zip(map(Vector, origins.tolist()), map(Vector, directions.tolist()))):
            location, normal, face, hit_distance = ray_cast(origin, direction, max_distance)
            if location is not None:
                distance[i] = hit_distance
                facing[i] = normal.dot(direction)
                hit_face[i] = face
        return distance, facing, (hit_face >= 0) & self.sealed[np.maximum(hit_face, 0)]

    def free(self):
        self.tree = None


def ray_space(positions, linear, box=None):
    """The space rays are cast in: object shape as seen (its linear transform), centred.

    Parameters
    ----------
    positions : (v, 3) float64, object space
    linear : (3, 3) float64, the object's world matrix without translation
    box : ((3,), (3,)) float64, optional: the object-space box to centre on (by default that of ``positions``)

    Returns
    -------
    centre : (3,) float64, object-space centre of ``box``
    to_ray : callable ``(points, normals) -> (points, normals)`` for (k, 3) arrays
    """
    linear = np.asarray(linear, dtype=np.float64)
    if box is None:
        box = (column_min(positions), column_max(positions)) if len(positions) else (np.zeros(3), np.zeros(3))
    centre = 0.5 * (box[0] + box[1])
    normal_matrix = np.linalg.inv(linear)            # row vectors: n' = n @ inv(L)  ==  inv(L)^T n

    def to_ray(points, normals=None):
        moved = (points - centre) @ linear.T
        if normals is None:
            return moved
        turned = normals @ normal_matrix
        length = np.linalg.norm(turned, axis=-1, keepdims=True)
        return moved, turned / np.where(length > 0, length, 1.0)

    return centre, to_ray


def world_winding(triangles, linear):
    """``triangles`` (t, 3) wound as they look once the linear map ``linear`` (3, 3) is applied to their
    vertices: a map that mirrors (negative determinant, e.g. a scale of -1 on one axis) turns every face
    inside out, so the last two corners swap to keep the faces' normals where Blender shows them.  Casters
    take a hit face's normal from its winding (back faces, sealed pieces)."""
    triangles = np.asarray(triangles)
    return triangles[:, [0, 2, 1]] if np.linalg.det(np.asarray(linear, dtype=np.float64)) < 0.0 else triangles


def same_space(points, normals=None):
    """The identity map of :func:`ray_space`'s ``to_ray``, for points already in ray space."""
    return points if normals is None else (points, normals)


@dataclass
class RayPart:
    """The rays of one input mesh of a bake: their parameters, their caster, and the map from the mesh's
    object space to the ray space they are cast in."""

    params: AOParams
    caster: RayCaster
    to_ray: Callable = same_space


def world_reach(mesh, matrix, settings):
    """``(low (3,), high (3,), reach)``: the world box of ``mesh`` placed by ``matrix`` (4, 4) and how far its
    rays reach (the maximum distance :func:`ao_params` gives it): what scene geometry can occlude it.  Both
    leave out debris far out (:func:`rest_vertices`), as the rays' maximum distance does."""
    matrix = np.asarray(matrix, dtype=np.float64)
    rest = rest_vertices(mesh)
    world = (mesh.positions if rest is None else mesh.positions[rest]) @ matrix[:3, :3].T + matrix[:3, 3]
    low, high = (column_min(world), column_max(world)) if len(world) else (np.zeros(3), np.zeros(3))
    reach = 0.5 * mesh_size(world) if settings.auto_distance else settings.max_distance
    return low, high, reach


def ray_part(mesh, matrix, settings, make_caster, occluders=None, rays=None, source=None):
    """The :class:`RayPart` of one mesh of a bake.

    Ray space has the world's axes and scale (what the object looks like) with
    the mesh's bounding-box centre at the origin, so positions stay small for
    float32 BVHs even far from the world origin.  The caster is made from the
    mesh in ray space, plus the ``occluders`` (the scene geometry within the
    maximum ray distance: :func:`world_reach`), and which triangles belong to
    sealed pieces (:mod:`..mesh.sealed`).

    Parameters
    ----------
    mesh : TriangleMesh
    matrix : (4, 4) float, the object's world matrix
    settings : BakeSettings
    make_caster : callable ``(positions, triangles, sealed) -> RayCaster``
    occluders : iterable of ``(world positions (v, 3), triangles (t, 3))``, optional: scene occluders, each
        triangle wound counter-clockwise seen from the front in world space (:func:`world_winding`)
    rays : int, optional, overrides the settings' ray count
    source : object, optional, what the caller read ``mesh`` from (opaque here: the Blender side's copy of the
        evaluated mesh), handed to ``make_caster(..., source=source)`` where the caster's occluders are the
        mesh alone, wound as read (no scene occluders, no mirroring matrix)
    """
    matrix = np.asarray(matrix, dtype=np.float64)
    rest = rest_vertices(mesh)
    # a spike to a stray vertex (or a loose one far out): centred on the rest, sized by the rest
    centre, to_ray = ray_space(mesh.positions, matrix[:3, :3], box=None if rest is None else mesh.box)
    own = to_ray(mesh.positions)
    params = ao_params(settings, own, rays, rest=None if rest is None else own[rest])
    positions, triangles = [own], [world_winding(mesh.triangles, matrix[:3, :3])]
    if occluders is not None:
        shift = matrix[:3, :3] @ centre + matrix[:3, 3]               # ray space + shift = world
        for world_positions, other_triangles in occluders:
            triangles.append(other_triangles + sum(len(p) for p in positions))
            positions.append(world_positions - shift)
    # the mesh alone: its own pieces (kept on the mesh, the proxy layout read them), moved into ray space as a whole
    vertex_piece = mesh.vertex_piece if len(positions) == 1 else None
    as_read = len(positions) == 1 and np.linalg.det(matrix[:3, :3]) >= 0.0      # the mesh alone, wound as read
    positions, triangles = np.concatenate(positions), np.concatenate(triangles)
    sealed = sealed_triangles(positions, triangles, vertex_piece=vertex_piece)
    if source is not None and as_read:
        return RayPart(params, make_caster(positions, triangles, sealed, source=source), to_ray)
    return RayPart(params, make_caster(positions, triangles, sealed), to_ray)
