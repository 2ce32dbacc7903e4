"""Read Blender meshes into the core's arrays: the baked objects as they render, and scene occluders
(objects, collection instances, Geometry Nodes and particle instances, modifier stacks evaluated).

A bake reads everything inside :func:`render_evaluation`: modifiers shown at
render time are shown, those hidden at render time hidden, Subdivision and
Multires at their render levels.  So the AO that renders is the AO of the
surface that renders, whatever the viewport shows.
"""

import contextlib
from dataclasses import dataclass

import numpy as np

from ...core.keys import STACK_MODIFIER
from ...core.mesh import TriangleMesh, boxes_near
from ...core.rays import world_winding

#: Modifiers whose viewport and render levels may differ: (viewport property, render property).
LEVELS = {"SUBSURF": ("levels", "render_levels"), "MULTIRES": ("levels", "render_levels")}


def vertex_positions(mesh):
    """(3v,) float32 vertex positions of a ``bpy.types.Mesh``, flat."""
    return _copy(mesh, "position", "vector", mesh.vertices, "co", np.empty(len(mesh.vertices) * 3, np.float32))


def loop_vertices(mesh):
    """(l,) int32 vertex of each loop (face corner)."""
    return _copy(mesh, ".corner_vert", "value", mesh.loops, "vertex_index", np.empty(len(mesh.loops), np.int32))


def _copy(mesh, attribute, key, elements, name, out):
    """Fill ``out`` from ``mesh.attributes[attribute]``, copied in one go, or where the mesh has no such
    attribute from ``elements``' property ``name``, which goes element by element (vertices' ``co`` and
    loops' ``vertex_index``: 18 ms for 500k loops, against under 1 ms)."""
    if attribute in mesh.attributes:
        mesh.attributes[attribute].data.foreach_get(key, out)
    else:
        elements.foreach_get(name, out)
    return out


def triangle_arrays(mesh):
    """Vertex positions (v, 3) float64 and Blender's triangulation (t, 3) int64 of a ``bpy.types.Mesh``."""
    mesh.calc_loop_triangles()
    positions = vertex_positions(mesh)
    triangles = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    return positions.reshape(-1, 3).astype(np.float64), triangles.reshape(-1, 3).astype(np.int64)


def read_triangles(mesh):
    """A :class:`~..core.mesh.TriangleMesh` of a ``bpy.types.Mesh``, in object space.

    Returns
    -------
    triangle_mesh : TriangleMesh
        Faces are the mesh's polygons, triangulated by Blender (concave n-gons
        included); corner normals are Blender's (custom normals, sharp edges
        and flat shading respected).
    triangle_loops : (t, 3) int64
        Loop (face corner) index of each triangle corner, to write UVs back.
    """
    positions, triangles = triangle_arrays(mesh)
    count = len(triangles)
    loops = np.empty(count * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    polygon = np.empty(count, dtype=np.int32)
    mesh.loop_triangles.foreach_get("polygon_index", polygon)
    corner_normals = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    if len(mesh.loops):
        mesh.corner_normals.foreach_get("vector", corner_normals)
    loops = loops.reshape(-1, 3).astype(np.int64)
    triangle_mesh = TriangleMesh(
        positions,
        triangles,
        polygon,
        corner_normals.reshape(-1, 3)[loops] if count else np.zeros((0, 3, 3)),
        face_count=len(mesh.polygons),
    )
    return triangle_mesh, loops


@dataclass
class Topology:
    """The evaluated mesh's corners as a bake saw them, enough to rebuild a mesh with the same corner order
    (where a Seamless AO modifier finds the UVs it stores, by corner index)."""

    positions: np.ndarray        # (v, 3) float32
    corner_vert: np.ndarray      # (l,) int32, the vertex of each corner
    loop_start: np.ndarray       # (f,) int32, each face's first corner

    @classmethod
    def of(cls, mesh):
        loop_start = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_start", loop_start)
        return cls(vertex_positions(mesh).reshape(-1, 3), loop_vertices(mesh), loop_start)

    def counts(self):
        """``(points, faces, corners)``, what the modifier compares to know the stack still fits."""
        return len(self.positions), len(self.loop_start), len(self.corner_vert)

    def same_as(self, mesh):
        """True if ``mesh`` (a ``bpy.types.Mesh``) has these counts and these corners' vertices."""
        return ((len(mesh.vertices), len(mesh.polygons), len(mesh.loops)) == self.counts()
                and np.array_equal(loop_vertices(mesh), self.corner_vert))


@contextlib.contextmanager
def render_evaluation(objects):
    """``with render_evaluation(objects):`` the depsgraph evaluates these objects as they render.

    Every modifier's viewport switch takes its render switch, Subdivision and
    Multires take their render levels, and Seamless AO's own modifier (it only
    carries UV maps) is off; all of it is put back on exit.
    """
    changed = []

    def change(owner, name, value):
        if getattr(owner, name) != value:
            changed.append((owner, name, getattr(owner, name)))
            setattr(owner, name, value)
    try:
        for ob in objects:
            for modifier in getattr(ob, "modifiers", ()):
                ours = modifier.type == "NODES" and modifier.name == STACK_MODIFIER
                change(modifier, "show_viewport", False if ours else modifier.show_render)
                viewport, render = LEVELS.get(modifier.type, (None, None))
                if viewport is not None:
                    change(modifier, viewport, getattr(modifier, render))
        yield
    finally:
        for owner, name, value in reversed(changed):
            setattr(owner, name, value)


@contextlib.contextmanager
def evaluated_mesh(ob, depsgraph):
    """``with evaluated_mesh(ob, depsgraph) as mesh``: ``ob``'s mesh with modifiers applied, freed on exit."""
    evaluated = ob.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        yield mesh
    finally:
        evaluated.to_mesh_clear()


def read_object(ob, depsgraph):
    """``ob`` as ``depsgraph`` evaluates it: :func:`read_triangles` of its evaluated mesh, and that mesh's
    :class:`Topology`, and whether its corners are its base mesh's (the bake's UV maps can then be written
    on the base mesh, which deforming modifiers carry through)."""
    with evaluated_mesh(ob, depsgraph) as mesh:
        triangle_mesh, loops = read_triangles(mesh)
        topology = Topology.of(mesh)
    return triangle_mesh, loops, topology, topology.same_as(ob.data)


def world_boxes(depsgraph):
    """``(instances, low (k, 3), high (k, 3))``: every mesh the depsgraph shows (objects, collection instances,
    Geometry Nodes and particle instances, modifiers evaluated), each as ``((evaluated mesh, original
    object), world matrix, is an instance)``, with its world bounding box (read once per bake: with hundreds of objects baked
    together, reading them again for each took seconds).

    The object an instance hands over lives only while the iteration stands on it (reading it later crashed
    Blender now and then), so what is kept is its evaluated mesh and its original object, taken there."""
    instances, corners = [], []
    for instance in depsgraph.object_instances:
        ob = instance.object
        if ob.type != "MESH":
            continue
        instances.append(((ob.data, ob.original), np.array(instance.matrix_world, dtype=np.float64),
                          bool(instance.is_instance)))
        corners.append(np.array(ob.bound_box, dtype=np.float64))
    if not instances:
        return instances, np.zeros((0, 3)), np.zeros((0, 3))
    matrices = np.array([matrix for _, matrix, _ in instances])
    world = np.einsum("kij,kcj->kci", matrices[:, :3, :3], np.array(corners)) + matrices[:, None, :3, 3]
    return instances, world.min(axis=1), world.max(axis=1)


def scene_occluders(boxes, exclude, low, high, reach):
    """``[(world positions (v, 3) float64, triangles (t, 3) int64)]`` of the meshes of ``boxes`` (see
    :func:`world_boxes`) whose bounds come within ``reach`` (the maximum ray distance) of the world box
    ``low``..``high`` of what is baked: farther ones cannot occlude, so they are not even read.  The object
    ``exclude`` (the baked one) is left out where it stands itself, not where an instance shows a copy.
    Meshes shown many times (scattered instances) are read once."""
    instances, lows, highs = boxes
    geometry, cache = [], {}
    if not instances:
        return geometry
    for ((mesh, original), matrix, is_instance), keep in zip(instances, boxes_near(low, high, lows, highs, reach)):
        if not keep or (not is_instance and original == exclude):
            continue
        key = mesh.as_pointer()
        if key not in cache:
            cache[key] = triangle_arrays(mesh)
        positions, triangles = cache[key]
        if len(triangles):
            geometry.append((positions @ matrix[:3, :3].T + matrix[:3, 3], world_winding(triangles, matrix[:3, :3])))
    return geometry
