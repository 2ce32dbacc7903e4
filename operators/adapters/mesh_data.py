"""Read Blender meshes into the core's arrays: the baked objects as they render, and scene occluders
(objects, collection instances, Geometry Nodes and particle instances, modifier stacks evaluated).

A bake reads everything inside :func:`render_evaluation`: modifiers shown at
render time are shown, those hidden at render time hidden, Subdivision and
Multires at their render levels.  So the AO that renders is the AO of the
surface that renders, whatever the viewport shows.
"""

import contextlib
from dataclasses import dataclass

import bpy
import numpy as np

from ...core.arrays.graph import index_type
from ...core.keys import STACK_MODIFIER, TEMP_PREFIX
from ...core.mesh.corner_values import CornerValues
from ...core.mesh.triangle_mesh import MeshArrays, boxes_near
from ...core.rays.ray_setup import world_winding
from ...shaders.island_nodes import ISLAND_ATTRIBUTE, island_group

#: A mesh of at least this many triangles gets its islands from Blender's Mesh Island node (:func:`islands_as_read`);
#: a smaller one is joined triangle by triangle in numpy, which costs less than setting up the node's evaluation (a
#: bake of hundreds of small objects would pay that set-up once per object).
ISLANDS_FROM_TRIANGLES = 1 << 15

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


def mesh_from_triangles(name, positions, triangles):
    """A new ``bpy.types.Mesh`` of triangles, written as :func:`_copy` reads (whole attributes at once).

    Parameters
    ----------
    name : str
    positions : (v, 3) float, written as float32
    triangles : (t, 3) int, vertex indices
    """
    mesh = bpy.data.meshes.new(name)
    positions = np.asarray(positions, dtype=np.float32).reshape(-1, 3)
    triangles = np.asarray(triangles, dtype=np.int32).reshape(-1, 3)
    mesh.vertices.add(len(positions))
    mesh.attributes["position"].data.foreach_set("vector", positions.ravel())
    mesh.loops.add(triangles.size)
    if ".corner_vert" in mesh.attributes:            # loops' "vertex_index" goes loop by loop (35 ms per 750k)
        mesh.attributes[".corner_vert"].data.foreach_set("value", triangles.ravel())
    else:
        mesh.loops.foreach_set("vertex_index", triangles.ravel())
    mesh.polygons.add(len(triangles))
    mesh.polygons.foreach_set("loop_start", np.arange(0, triangles.size, 3, dtype=np.int32))
    mesh.update()
    return mesh


@dataclass
class OccluderCopy:
    """A temporary copy of an evaluated mesh a bake read, for its ray caster to cast against instead of a mesh
    built anew from the triangles (:func:`mesh_from_triangles`, which has Blender work out every edge again).
    The copy shares the evaluated mesh's arrays until written to, and has no materials.

    Attributes
    ----------
    mesh : bpy.types.Mesh, its vertices those the bake read, its triangulation Blender's, as read
    triangle_face : (t,) int, the face of each triangle the bake read
    """

    mesh: object
    triangle_face: np.ndarray

    def fits(self, vertices, triangles):
        """True if the copy still is what was read: ``vertices`` and ``triangles`` (counts)."""
        mesh = self.mesh
        return len(mesh.vertices) == vertices and len(mesh.loops) - 2 * len(mesh.polygons) == triangles


def _evaluated_copy(ob, depsgraph, name):
    """A new mesh ``name``: ``ob`` as ``depsgraph`` evaluates it, no materials (it shares the evaluated mesh's
    arrays until written to)."""
    mesh = bpy.data.meshes.new_from_object(ob.evaluated_get(depsgraph), preserve_all_data_layers=False,
                                           depsgraph=depsgraph)
    mesh.name = name
    mesh.materials.clear()
    return mesh


def occluder_copy(ob, depsgraph, arrays):
    """An :class:`OccluderCopy` of ``ob`` as ``depsgraph`` evaluates it, read as ``arrays`` (MeshArrays), or None
    where the copy does not have the vertices and triangles read (it is then removed)."""
    mesh = _evaluated_copy(ob, depsgraph, TEMP_PREFIX + "occluders")
    copy = OccluderCopy(mesh, np.asarray(arrays.triangle_face))
    if not copy.fits(len(arrays.positions), len(arrays.triangles)):
        bpy.data.meshes.remove(mesh)
        return None
    return copy


def vertex_islands(mesh):
    """(v,) int32: the island of every vertex of ``mesh`` (a ``bpy.types.Mesh`` no object uses, such as an
    :class:`OccluderCopy`'s), vertices joined through its faces, ``0 ..``: Blender's Mesh Island node, evaluated
    on all cores in a temporary scene, what :func:`...core.mesh.weld.vertex_pieces` takes as ``islands``
    instead of joining every triangle itself in numpy.  None where the mesh has loose edges
    (edges in no face: the node would join their vertices, the triangles do not) or no vertices.
    """
    if not len(mesh.vertices) or not len(mesh.loops):
        return None
    corner_edge = np.empty(len(mesh.loops), dtype=np.int32)
    _copy(mesh, ".corner_edge", "value", mesh.loops, "edge_index", corner_edge)
    if np.count_nonzero(np.bincount(corner_edge, minlength=len(mesh.edges))) != len(mesh.edges):
        return None
    made = []
    try:
        scene = bpy.data.scenes.new(TEMP_PREFIX + "islands")
        made.append(scene)
        group = island_group(TEMP_PREFIX + "islands")
        made.append(group)
        reader = bpy.data.objects.new(TEMP_PREFIX + "islands", mesh)
        made.append(reader)
        scene.collection.objects.link(reader)
        reader.modifiers.new("islands", "NODES").node_group = group
        with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0]):
            depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = reader.evaluated_get(depsgraph).data
        if len(evaluated.vertices) != len(mesh.vertices) or ISLAND_ATTRIBUTE not in evaluated.attributes:
            return None
        island = np.empty(len(mesh.vertices), dtype=np.int32)
        evaluated.attributes[ISLAND_ATTRIBUTE].data.foreach_get("value", island)
        return island
    finally:
        bpy.data.batch_remove(made)


def islands_as_read(ob, depsgraph, arrays, copy=None):
    """:func:`vertex_islands` of ``ob`` as ``depsgraph`` evaluates it, read as ``arrays`` (MeshArrays): of
    ``copy`` (its :class:`OccluderCopy`) where given, else of a temporary copy; None where the mesh has fewer
    than :data:`ISLANDS_FROM_TRIANGLES` triangles, has loose edges or does not have the vertices read."""
    if len(arrays.triangles) < ISLANDS_FROM_TRIANGLES:
        return None
    mesh = copy.mesh if copy is not None else _evaluated_copy(ob, depsgraph, TEMP_PREFIX + "islands")
    try:
        return vertex_islands(mesh) if len(mesh.vertices) == len(arrays.positions) else None
    finally:
        if copy is None:
            bpy.data.meshes.remove(mesh)


def remove_occluder_copies(copies):
    """Remove the copies' meshes that no caster took over (safe to call twice)."""
    remove_present([copy.mesh for copy in copies if copy is not None])


def remove_present(datablocks):
    """Remove those of ``datablocks`` still there (one removed already is skipped) in one
    ``bpy.data.batch_remove``: removing them one by one scans every datablock each time (31 ms each with 400
    objects baked together)."""
    present = []
    for datablock in datablocks:
        try:
            datablock.name                           # still there?
            present.append(datablock)
        except ReferenceError:
            pass
    if present:
        bpy.data.batch_remove(present)


def read_uv(mesh, name):
    """(l, 2) float32 UVs of the UV map ``name`` of a ``bpy.types.Mesh``, one per loop."""
    uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    _copy(mesh, name, "vector", mesh.uv_layers[name].data, "uv", uv)
    return uv.reshape(-1, 2)


def write_uv(mesh, name, uv):
    """Set the UV map ``name`` (it exists) of a ``bpy.types.Mesh`` to ``uv`` (l, 2): through its attribute, in
    one copy (its ``uv`` property goes loop by loop: 23 ms per 280k loops, against under 1 ms)."""
    uv = np.ascontiguousarray(uv, dtype=np.float32).ravel()
    if name in mesh.attributes:
        mesh.attributes[name].data.foreach_set("vector", uv)
    else:
        mesh.uv_layers[name].data.foreach_set("uv", uv)


def triangle_loops(mesh):
    """(t, 3) int32 loop (face corner) of each corner of Blender's triangulation of a ``bpy.types.Mesh``
    (Blender's own type: kept through a bake to write the UVs, half of an int64 copy)."""
    if len(mesh.loops) == 3 * len(mesh.polygons):
        # every face a triangle (each has three corners or more): Blender's triangles are the faces' corners in
        # order, and loop_triangles' "loops" go through Blender's API triangle by triangle
        return np.arange(len(mesh.loops), dtype=np.int32).reshape(-1, 3)
    mesh.calc_loop_triangles()
    loops = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    return loops.reshape(-1, 3)


def triangle_arrays(mesh, loops=None):
    """Vertex positions (v, 3) float64 and Blender's triangulation (t, 3) int64 of a ``bpy.types.Mesh``
    (``loops``: its :func:`triangle_loops`, when the caller has them)."""
    loops = triangle_loops(mesh) if loops is None else loops
    positions = vertex_positions(mesh)
    return positions.reshape(-1, 3).astype(np.float64), loop_vertices(mesh).astype(np.int64)[loops]


def triangle_polygons(mesh, count):
    """(t,) int32 polygon of each of the ``count`` triangles of Blender's triangulation."""
    polygon = np.empty(count, dtype=np.int32)
    if hasattr(mesh, "loop_triangle_polygons"):       # one copy; loop_triangles' polygon_index goes one by one
        mesh.loop_triangle_polygons.foreach_get("value", polygon)
    else:
        mesh.loop_triangles.foreach_get("polygon_index", polygon)
    return polygon


def triangle_side_edges(mesh, loops, polygon):
    """(t, 3) int32 (int64 past 2**31 numbers): the edge of each side of Blender's triangles (side ``j`` from
    corner ``j`` to the next), for :attr:`~..core.mesh.triangle_mesh.TriangleMesh.side_edge`: the mesh's edge
    where the side is one of its face's, else (a quad's inner diagonal) one number past the edges for each face.
    None where a face has more than four corners (an n-gon's diagonals would need numbering one by one).

    ``loops`` (t, 3) int: :func:`triangle_loops`; ``polygon`` (t,) int: :func:`triangle_polygons`.  A triangle
    runs round its face's corners in their order, so its side from corner ``l`` is either the face's edge from
    ``l`` (``l``'s edge) or a diagonal.
    """
    corner_edge = np.empty(len(mesh.loops), dtype=np.int32)
    attribute = mesh.attributes.get(".corner_edge")
    if attribute is not None and len(attribute.data) == len(corner_edge):
        attribute.data.foreach_get("value", corner_edge)
    else:                                   # where the corners' edges are no attribute
        mesh.loops.foreach_get("edge_index", corner_edge)
    if len(mesh.loops) == 3 * len(mesh.polygons):          # triangles only: the corners in order (triangle_loops)
        return corner_edge[loops]
    triangles_of_face = np.bincount(polygon, minlength=len(mesh.polygons))
    if int(triangles_of_face.max(initial=0)) > 2:
        return None
    number = index_type(len(mesh.edges) + len(mesh.polygons))
    loops = np.asarray(loops, dtype=number)
    following = np.empty_like(loops)                            # the corner each side ends at
    following[:, :2] = loops[:, 1:]
    following[:, 2] = loops[:, 0]
    following -= loops
    # a quad's (two triangles') corners run l .. l + 3: its diagonals join corners two apart, its edges one or three
    diagonal = (np.abs(following) == 2) & (triangles_of_face == 2)[polygon][:, None]
    return np.where(diagonal, number(len(mesh.edges)) + np.asarray(polygon, dtype=number)[:, None],
                    corner_edge[loops].astype(number))


def read_mesh_arrays(mesh, corners=None):
    """A ``bpy.types.Mesh`` as :class:`~..core.mesh.triangle_mesh.MeshArrays`, in object space: one ``foreach_get`` per
    attribute, nothing worked out from them yet (its vertices and corners from ``corners``, its
    :class:`EvaluatedCorners` if already read).

    Returns
    -------
    arrays : MeshArrays
        Faces are the mesh's polygons, triangulated by Blender (concave n-gons
        included); corner normals are Blender's (custom normals, sharp edges
        and flat shading respected).
    triangle_loops : (t, 3) int32
        Loop (face corner) index of each triangle corner, to write UVs back.
    """
    loops = triangle_loops(mesh)
    count = len(loops)
    corner_normals = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    if len(mesh.loops):
        mesh.corner_normals.foreach_get("vector", corner_normals)
    polygon = triangle_polygons(mesh, count)
    positions, corner_vert = ((corners.positions, corners.corner_vert) if corners is not None else
                              (vertex_positions(mesh).reshape(-1, 3), loop_vertices(mesh)))
    arrays = MeshArrays(
        positions,
        corner_vert.astype(np.int64)[loops],
        polygon,
        CornerValues(corner_normals.reshape(-1, 3), loops),                # gathered for the texels only
        face_count=len(mesh.polygons),
        side_edge=triangle_side_edges(mesh, loops, polygon),
    )
    return arrays, loops


def read_triangles(mesh):
    """A :class:`~..core.mesh.triangle_mesh.TriangleMesh` of a ``bpy.types.Mesh`` (:func:`read_mesh_arrays`) and
    the loop of each triangle corner."""
    arrays, loops = read_mesh_arrays(mesh)
    return arrays.mesh(), loops


@dataclass
class EvaluatedCorners:
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
    """``ob`` as ``depsgraph`` evaluates it: :func:`read_mesh_arrays` of its evaluated mesh, and that mesh's
    :class:`EvaluatedCorners`, and whether its corners are its base mesh's (the bake's UV maps can then be written
    on the base mesh, which deforming modifiers carry through)."""
    with evaluated_mesh(ob, depsgraph) as mesh:
        corners = EvaluatedCorners.of(mesh)
        arrays, loops = read_mesh_arrays(mesh, corners)
    return arrays, loops, corners, corners.same_as(ob.data)


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
