"""What the material shows on an object's evaluated surface (the surface the viewport or a render gives),
for the tests and benchmarks of the Seamless AO modifier (``operators/adapters/stack.py``)."""

import bpy
import numpy as np
from mathutils.bvhtree import BVHTree

from accuracy import surface_samples
from blender_checks import image_array, uv_layer_array
from package import seamless_ao  # noqa: F401  (imports the add-on as ``seamless_ao``)
from seamless_ao.core.image.shown import blended_ao
from seamless_ao.operators.adapters.mesh_data import read_triangles


def shown_on_the_evaluated_surface(ob, image, count=1500):
    """What the material shows at visible points of ``ob``'s evaluated surface (the UV maps the Seamless AO
    modifier stores, read from that surface), the points' mesh and where they are."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = ob.evaluated_get(depsgraph)
    mesh_data = evaluated.to_mesh()
    try:
        mesh, loops = read_triangles(mesh_data)
        assert all(name in mesh_data.uv_layers for name in ("AO_X", "AO_Y", "AO_Z"))
        uv = [uv_layer_array(mesh_data, name) for name in ("AO_X", "AO_Y", "AO_Z")]
    finally:
        evaluated.to_mesh_clear()
    triangle, bary, normals = surface_samples(mesh, count, seed=2)
    layer_uv = np.stack([np.einsum("kc,kcd->kd", bary, layer[loops[triangle]]) for layer in uv], axis=1)
    return blended_ao(image_array(image), layer_uv, normals), mesh, triangle, bary, normals


def nearest_on(surface, points):
    """``(triangle, bary, normals)`` of the points of TriangleMesh ``surface`` nearest ``points`` (k, 3)."""
    tree = BVHTree.FromPolygons(surface.positions.tolist(), surface.triangles.tolist(), all_triangles=True)
    triangle, bary = [], []
    for point in points:
        location, _, face, _ = tree.find_nearest(point.tolist())
        corners = surface.positions[surface.triangles[face]]
        triangle.append(face)
        bary.append(np.linalg.lstsq(np.vstack([corners.T, np.ones(3)]), np.append(location, 1.0), rcond=None)[0])
    triangle, bary = np.array(triangle), np.array(bary)
    normals = np.einsum("kc,kcd->kd", bary, surface.corner_normals[triangle])
    return triangle, bary, normals / np.linalg.norm(normals, axis=1, keepdims=True)


def evaluated_surface(ob):
    """``ob``'s surface as the depsgraph evaluates it now (viewport levels, unless set otherwise), as a
    TriangleMesh."""
    evaluated = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
    try:
        return read_triangles(evaluated.to_mesh())[0]
    finally:
        evaluated.to_mesh_clear()
