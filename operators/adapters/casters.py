"""The Blender side of a bake's rays: a ray caster on Blender's Geometry Nodes Raycast node (multi-threaded),
a :class:`~...core.rays.ray_setup.RayCaster`; the Cycles caster, the same plus Cycles' AO
bake at texels (:mod:`.cycles_caster`); and :func:`caster_maker`, which picks one of them or core's
``BVHCaster`` for the settings.

The rays of one batch become the vertices of a temporary point mesh with a
``ray_dir`` attribute; a node group (:mod:`...shaders.raycast_nodes`) casts
them against a temporary occluder mesh and stores hit distance and facing as
attributes, read back with ``foreach_get``.  Everything lives in a temporary scene, evaluated through a
context override, so the user's scenes, objects and undo history are never
touched; :meth:`NodesCaster.free` removes every datablock it made.

Same interface as :class:`...core.rays.ray_setup.BVHCaster`; same BVH underneath (Blender's),
but the node evaluates the rays on all cores.  Blender 4.2 and 4.3 build that BVH again at every evaluation
(:data:`RAYCAST_KEEPS_BVH`): there small batches are cast one ray at a time on a ``mathutils`` BVH built once.
"""

import os

import bpy
import numpy as np

from ...core.keys import TEMP_PREFIX
from ...core.rays.ray_setup import BVHCaster, RayCaster
from ...shaders.raycast_nodes import raycast_group
from .cycles_caster import CyclesAmbientOcclusion, cycles_enabled
from .mesh_data import mesh_from_triangles, remove_present

#: An occluder of at least this many triangles gets its BVH built by a cast of one ray before its first batch.
#: The Raycast node builds the BVH at its first evaluation.  In Blender 5.0, when that evaluation is a batch of
#: rays, the build runs while the rays are evaluated on all cores and takes about as long as on one: at a million
#: triangles the batch's first cast took longer than one ray's and the batch's after it together (4.2 and 5.2
#: take as long either way).  One ray costs one more evaluation, which a small occluder's BVH does not repay.
BUILD_ALONE_FROM_TRIANGLES = 1 << 16
#: Whether the Raycast node keeps its target's BVH from one evaluation to the next.  Blender 4.2 and 4.3 cast
#: against a copy of the target made at each evaluation, which keeps no BVH: every batch builds it anew (a batch of
#: 1,000 rays took 0.21 s at a million triangles in 4.2, 5 to 8 ms in 4.4 to 5.2), and a one-ray build before the
#: first batch only adds one more (tests/bench/bench_raycast_evaluations.py).
RAYCAST_KEEPS_BVH = bpy.app.version >= (4, 4, 0)
#: Where it does not, a batch of fewer rays than this many per occluder triangle, on 2 cores, is cast one ray at
#: a time on a ``mathutils`` BVH of the occluder built once (:meth:`NodesCaster.cast`): below it, the BVH the node
#: builds costs more than what its cores save on the rays (on 2 cores a ray alone took longer than in the node on a
#: smooth Suzanne, and less on a noisy scan).  Cast so, the cheapest bake of the 250k- and 1M-triangle
#: Suzannes in 4.2 took 0.86 and 0.74 times as long as with every batch through the node (the same bench).  With
#: more cores the node's share of each falls, and so does this (:func:`single_rays_below`; not measured here).
SINGLE_RAYS_PER_TRIANGLE = 0.1


class NodesCaster(RayCaster):
    """Ray caster evaluated by Geometry Nodes.

    Parameters
    ----------
    positions : (v, 3) float, ray space
    triangles : (t, 3) int
    sealed : (t,) bool, optional, triangles of closed pieces (core/mesh/sealed.py; none if not given)
    source : mesh_data.OccluderCopy, optional: the evaluated mesh these triangles were read from (Blender's
        triangulation of its faces, as wound), copied; the caster takes it over, moves its vertices to
        ``positions`` and casts against it instead of a mesh built anew (Blender triangulates the moved faces as
        it did the read ones, but for a quad so bent that the move flips its choice of diagonal).  ``sealed``
        must then be the same for every triangle of a face (it is: it is a piece's).
    """

    name = "GEOMETRY_NODES"

    def __init__(self, positions, triangles, sealed=None, source=None):
        self._datablocks = []
        self.scene = self._temporary(bpy.data.scenes.new(TEMP_PREFIX + "scene"))
        if source is not None and source.fits(len(positions), len(triangles)):
            occluder_mesh, triangle_face = self._temporary(source.mesh), source.triangle_face
            occluder_mesh.attributes["position"].data.foreach_set(
                "vector", np.asarray(positions, dtype=np.float32).ravel())
            occluder_mesh.update()                       # its positions changed: nothing cached for the old ones
            if "sealed" in occluder_mesh.attributes:           # the user's own, of that name
                occluder_mesh.attributes.remove(occluder_mesh.attributes["sealed"])
        else:
            occluder_mesh = self._temporary(mesh_from_triangles(TEMP_PREFIX + "occluders", positions, triangles))
            triangle_face = np.arange(len(triangles))              # a face per triangle
        flag = np.zeros(len(triangles), dtype=np.float32) if sealed is None else np.asarray(sealed, dtype=np.float32)
        on_vertices = vertex_flags(len(occluder_mesh.vertices), triangles, flag)
        if on_vertices is not None:
            occluder_mesh.attributes.new("sealed", "FLOAT", "POINT").data.foreach_set("value", on_vertices)
        else:
            face_flag = np.zeros(len(occluder_mesh.polygons), dtype=np.float32)
            face_flag[triangle_face] = flag
            occluder_mesh.attributes.new("sealed", "FLOAT", "FACE").data.foreach_set("value", face_flag)
        self.occluder = self._temporary(bpy.data.objects.new(TEMP_PREFIX + "occluders", occluder_mesh))
        self.scene.collection.objects.link(self.occluder)
        # Hide the occluder from the render, it only serves as the node's target.
        self.occluder.hide_render = True
        self.build_alone = RAYCAST_KEEPS_BVH and len(triangles) >= BUILD_ALONE_FROM_TRIANGLES
        # where the node builds its BVH at every batch, small batches go to one mathutils BVH (of the faces)
        self.single_rays_below = 0 if RAYCAST_KEEPS_BVH else single_rays_below(len(triangles))
        if self.single_rays_below:
            self.face_sealed = np.zeros(len(occluder_mesh.polygons), dtype=bool)
            self.face_sealed[triangle_face] = flag > 0.5
        self.single = None
        self.points = None
        self._set_up_raycast()

    def _temporary(self, datablock):
        self._datablocks.append(datablock)
        return datablock

    def _set_up_raycast(self):
        """The points that cast the rays and their Raycast node group."""
        self.points_mesh = self._temporary(bpy.data.meshes.new(TEMP_PREFIX + "rays"))
        self.points = self._temporary(bpy.data.objects.new(TEMP_PREFIX + "rays", self.points_mesh))
        self.scene.collection.objects.link(self.points)
        self.group, self.cast_node = raycast_group(TEMP_PREFIX + "raycast", self.occluder)
        self._temporary(self.group)
        modifier = self.points.modifiers.new("raycast", "NODES")
        modifier.node_group = self.group
        self.bvh_built = False              # the Raycast node builds it at its first evaluation

    def _release_raycast(self):
        """Remove the points and their node group, and give the occluder a copy of its mesh: Blender keeps the
        BVH the Raycast node built (160 MB a million triangles) with the mesh it was built for.  The copy
        shares the mesh's arrays, and moving one vertex onto itself tells Blender its positions changed, so
        the copy lets go of that BVH too.  A later :meth:`cast` sets it all up again."""
        if self.points is None:
            return
        old = self.occluder.data
        mesh = self._temporary(old.copy())
        if len(mesh.vertices):
            mesh.vertices[0].co = mesh.vertices[0].co
        self.occluder.data = mesh
        released = [self.points, self.points_mesh, self.group, old]
        self._datablocks = [block for block in self._datablocks if block not in released]
        bpy.data.batch_remove(released)
        self.points = self.points_mesh = self.group = self.cast_node = None
        self.single = None

    def cast(self, origins, directions, max_distance):
        if self.points is None:
            self._set_up_raycast()
        count = len(origins)
        distance = np.full(count, np.inf)
        facing = np.zeros(count)
        if not count:
            return distance, facing, np.zeros(count, dtype=bool)
        if count < self.single_rays_below:                         # see SINGLE_RAYS_PER_TRIANGLE
            return self._single_caster().cast(origins, directions, max_distance)
        if not self.bvh_built and self.build_alone and count > 1:
            self._evaluate(origins[:1], directions[:1], max_distance)       # see BUILD_ALONE_FROM_TRIANGLES
        hit = self._evaluate(origins, directions, max_distance)
        found = hit[:, 0] >= 0.0
        distance[found] = hit[found, 0]
        facing[found] = hit[found, 1]
        return distance, facing, found & (hit[:, 2] > 0.5)

    def _single_caster(self):
        """Core's caster over a ``mathutils`` BVH of the occluder as evaluated (its hits are its faces), built at
        the first use."""
        if self.single is None:
            from mathutils.bvhtree import BVHTree

            with bpy.context.temp_override(scene=self.scene, view_layer=self.scene.view_layers[0]):
                depsgraph = bpy.context.evaluated_depsgraph_get()
            self.single = BVHCaster.of_tree(BVHTree.FromObject(self.occluder, depsgraph), self.face_sealed)
        return self.single

    def _evaluate(self, origins, directions, max_distance):
        """(k, 3) float32 ``hit`` of rays from ``origins`` along ``directions`` (k, 3): the node group evaluated once
        on a point mesh of them."""
        count = len(origins)
        mesh = self.points_mesh
        mesh.clear_geometry()
        mesh.vertices.add(count)
        # through the position attribute: vertices.foreach_set("co") costs a fifth of the cast (50 ms per 500k)
        mesh.attributes["position"].data.foreach_set("vector", np.asarray(origins, dtype=np.float32).ravel())
        mesh.attributes.new("ray_dir", "FLOAT_VECTOR", "POINT").data.foreach_set(
            "vector", np.asarray(directions, dtype=np.float32).ravel())
        if self.cast_node.inputs["Ray Length"].default_value != float(max_distance):
            self.cast_node.inputs["Ray Length"].default_value = float(max_distance)
        mesh.update()
        with bpy.context.temp_override(scene=self.scene, view_layer=self.scene.view_layers[0]):
            depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = self.points.evaluated_get(depsgraph).data
        hit = np.empty(count * 3, dtype=np.float32)
        evaluated.attributes["hit"].data.foreach_get("vector", hit)
        self.bvh_built = True
        return hit.reshape(-1, 3)

    def free(self):
        """Remove every temporary datablock (safe to call twice)."""
        free_casters([self])


def single_rays_below(triangles, cores=None):
    """Batches of fewer rays than this are cast one ray at a time on an occluder of ``triangles`` where the node
    builds its BVH at every batch: :data:`SINGLE_RAYS_PER_TRIANGLE` a triangle on 2 cores, shrunk as the node's
    work is shared by more (``cores``: the machine's by default)."""
    cores = max(1, cores if cores is not None else (os.cpu_count() or 1))
    return SINGLE_RAYS_PER_TRIANGLE * triangles * min(1.0, 2.0 / cores)


def vertex_flags(vertex_count, triangles, flag):
    """(v,) float32: each vertex's ``flag`` (t,) float32 of the triangles on it, where all of them have the same
    (else 0); None where some vertex's triangles differ.

    The casters' flag is the sealed test's, made piece by piece, and no vertex is in two pieces
    (:mod:`...core.mesh.sealed`): the Raycast node then reads it from the vertices at a hit.  On the vertices, not
    the faces, where it can: Blender 5.0 spreads a face attribute to the vertices at every evaluation of the
    node (25 ms a batch at two million triangles, 5 ms on the vertices)."""
    triangles = np.asarray(triangles)
    on_vertices = np.zeros(vertex_count, dtype=np.float32)
    on_vertices[triangles.ravel()] = np.repeat(flag, 3)
    if not np.array_equal(on_vertices[triangles], np.broadcast_to(flag[:, None], triangles.shape)):
        return None
    return on_vertices


class CyclesCaster(CyclesAmbientOcclusion, NodesCaster):
    """The Cycles caster: :class:`NodesCaster` whose ``ambient_occlusion`` bakes Cycles' AO at given texels
    (:mod:`.cycles_caster`), which :class:`...core.rays.job.AOJob` hands all but the pilot rays to."""

    name = "CYCLES"
    bakes_whole_texels = True
    #: What cast every ray when no part had enough rays left after the pilot for Cycles (core/rays/job.py).
    pilot_name = NodesCaster.name

    def __init__(self, positions, triangles, sealed=None, source=None):
        super().__init__(positions, triangles, sealed, source)
        # Cycles' device is asked for at its first bake: a bake whose rays all go to the node never asks
        self.device, self.warnings = None, []

    def casting_done(self):
        """Only Cycles bakes are left: let go of the Raycast node's set-up, and Blender's BVH with it, before
        Cycles builds its own (:meth:`NodesCaster._release_raycast`)."""
        self._release_raycast()


def free_casters(casters):
    """Remove the temporary datablocks of all ``casters`` at once (:func:`.mesh_data.remove_present`)."""
    datablocks = []
    for caster in casters:
        datablocks += getattr(caster, "_datablocks", ())
        if hasattr(caster, "_datablocks"):
            caster._datablocks.clear()
        if getattr(caster, "single", None) is not None:           # a mathutils BVH (NodesCaster._single_caster)
            caster.single = None
    remove_present(datablocks)


def caster_maker(settings):
    """What makes a bake's casters, ``(positions, triangles, sealed) -> caster``: the Geometry Nodes caster,
    core's Python loop over mathutils' BVH, or the Cycles caster (:mod:`.cycles_caster`), as
    ``settings.caster_name()`` says (``ray_caster``, Automatic resolved: never to Cycles where it is not enabled)."""
    caster = settings.caster_name(cycles_enabled())
    if caster == "CYCLES":
        return CyclesCaster
    return BVHCaster if caster == "PYTHON_BVH" else NodesCaster
