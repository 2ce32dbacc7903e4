"""The demo's built-in scenes (the thesis' test scenes), made with bpy: Suzanne, a Cornell box with two
blocks, a sphere hovering over a plane, and the three side by side (:func:`demo_scene`).

The tests and benchmarks bake the same scenes (``tests/support/blender_scenes.py`` takes them from here).
"""

import bmesh
import bpy
from mathutils import Matrix


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


def cornell_box(name="Cornell Box"):
    """An open-front room 2 x 2 x 2 with a tall and a short block, as one mesh (inward walls)."""
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
        bmesh.ops.rotate(bm, matrix=Matrix.Rotation(angle, 3, "Z"), verts=verts)
        bmesh.ops.translate(bm, vec=center, verts=verts)
    bm.normal_update()
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    # subdivide so the flat walls are not single huge quads
    return add_object(name, mesh)


def sphere_over_plane(name="Sphere Over Plane"):
    """A UV sphere hovering just above a square plane, as one mesh (thesis scene 2)."""
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


def mesh_from_faces(name, positions, faces):
    """A mesh from positions (v, 3) and faces (lists of vertex indices, any length)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(map(float, p)) for p in positions], [], [tuple(map(int, f)) for f in faces])
    mesh.validate()
    return mesh


def demo_scene():
    """The demo scene: Cornell box, sphere over plane, Suzanne side by side. Returns the objects."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    box = cornell_box()
    box.location = (-3.0, 0.0, 0.0)
    sphere = sphere_over_plane()
    monkey = suzanne(2)
    monkey.location = (3.0, 0.0, 1.0)
    return [box, sphere, monkey]
