"""Meshes and scenes made with bpy, for tests and the demo."""

import bpy
import numpy as np


def add_object(name, mesh):
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def suzanne(subdivisions=2, name="Suzanne", smooth=True):
    """Subdivided Suzanne with the subdivision applied (about 16k triangles at level 2)."""
    bpy.ops.mesh.primitive_monkey_add()
    ob = bpy.context.active_object
    ob.name = name
    if subdivisions:
        modifier = ob.modifiers.new("Subdivision", "SUBSURF")
        modifier.levels = subdivisions
        bpy.ops.object.modifier_apply(modifier=modifier.name)
    if smooth:
        for polygon in ob.data.polygons:
            polygon.use_smooth = True
    return ob


def mesh_from_arrays(name, positions, triangles, smooth=False):
    """A mesh of ``positions`` (v, 3) and ``triangles`` (t, 3), flat shaded unless ``smooth``."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(map(float, p)) for p in positions], [], [tuple(map(int, t)) for t in triangles])
    mesh.validate()
    if smooth:
        mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
        mesh.update()
    return mesh


def box_mesh(name, size, center):
    """An axis-aligned box mesh (quads) of ``size`` (3,) at ``center`` (3,)."""
    sx, sy, sz = (0.5 * s for s in size)
    cx, cy, cz = center
    verts = [(cx + x * sx, cy + y * sy, cz + z * sz) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.validate()
    return mesh


def cornell_box(name="Cornell Box"):
    """An open-front room 2 x 2 x 2 with a tall and a short block, as one mesh (inward walls)."""
    import bmesh
    bm = bmesh.new()
    walls = [
        [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)],        # floor, normal +Z
        [(-1, -1, 2), (-1, 1, 2), (1, 1, 2), (1, -1, 2)],        # ceiling, normal -Z
        [(-1, 1, 0), (1, 1, 0), (1, 1, 2), (-1, 1, 2)],          # back wall, normal -Y
        [(-1, -1, 0), (-1, 1, 0), (-1, 1, 2), (-1, -1, 2)],      # left wall, normal +X
        [(1, -1, 0), (1, -1, 2), (1, 1, 2), (1, 1, 0)],          # right wall, normal -X
    ]
    for quad in walls:
        bm.faces.new([bm.verts.new(v) for v in quad])
    for size, center, angle in (((0.6, 0.6, 1.2), (-0.35, 0.3, 0.6), 0.3), ((0.6, 0.6, 0.6), (0.4, -0.3, 0.3), -0.3)):
        result = bmesh.ops.create_cube(bm, size=1.0)
        verts = result["verts"]
        bmesh.ops.scale(bm, vec=size, verts=verts)
        from mathutils import Matrix
        bmesh.ops.rotate(bm, matrix=Matrix.Rotation(angle, 3, "Z"), verts=verts)
        bmesh.ops.translate(bm, vec=center, verts=verts)
    bm.normal_update()
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    # subdivide so the flat walls are not single huge quads
    return add_object(name, mesh)


#: The Cornell box's concave edges: (a point on the edge, its direction, the two faces' inward normals).
CORNELL_CONCAVE_EDGES = {
    "back/right wall": ((1.0, 1.0, 1.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0), (-1.0, 0.0, 0.0)),
    "back/left wall": ((-1.0, 1.0, 1.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0), (1.0, 0.0, 0.0)),
    "floor/back wall": ((0.3, 1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
    "floor/right wall": ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (-1.0, 0.0, 0.0)),
}


def cornell_concave_points(distances, along=np.linspace(-0.5, 0.5, 8)):
    """Points near the Cornell box's concave edges, on both faces of each.

    Yields ``(edge name, points (k, 3), normals (k, 3), distance (k,))`` per
    edge and face: ``along`` positions on the edge times ``distances`` (units)
    off it into the face.
    """
    for name, (start, direction, normal_a, normal_b) in CORNELL_CONCAVE_EDGES.items():
        for side, away in ((normal_a, normal_b), (normal_b, normal_a)):
            distance = np.repeat(distances, len(along))
            points = (np.asarray(start) + np.outer(np.tile(along, len(distances)), direction)
                      + distance[:, None] * np.asarray(away))
            yield name, points, np.tile(side, (len(points), 1)), distance


def sphere_over_plane(name="Sphere Over Plane"):
    """A UV sphere hovering just above a square plane, as one mesh (thesis scene 2)."""
    import bmesh
    from mathutils import Matrix
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=48, v_segments=24, radius=0.5,
                              matrix=Matrix.Translation((0, 0, 0.65)))
    bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=1.5)
    # bmesh's face order varies from process to process (it hashes pointers):
    # a canonical order (each face from its lowest vertex, faces sorted) makes
    # the mesh, and the benchmark's cached reference for it, the same every run.
    positions = [tuple(v.co) for v in bm.verts]
    faces = []
    for face in bm.faces:
        ring = [v.index for v in face.verts]
        first = ring.index(min(ring))
        faces.append(ring[first:] + ring[:first])
    bm.free()
    mesh = mesh_from_faces(name, positions, sorted(faces))
    for polygon in mesh.polygons:
        polygon.use_smooth = polygon.center.z > 0.01
    return add_object(name, mesh)


def demo_scene():
    """The demo scene: Cornell box, sphere over plane, Suzanne side by side. Returns the objects."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    box = cornell_box()
    box.location = (-3.0, 0.0, 0.0)
    sphere = sphere_over_plane()
    monkey = suzanne(2)
    monkey.location = (3.0, 0.0, 1.0)
    return [box, sphere, monkey]


def mesh_from_faces(name, positions, faces):
    """A mesh from positions (v, 3) and faces (lists of vertex indices, any length)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(map(float, p)) for p in positions], [], [tuple(map(int, f)) for f in faces])
    mesh.validate()
    return mesh
