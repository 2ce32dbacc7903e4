"""Error as the user sees it: the shown AO at random surface points against a many-ray reference."""

import numpy as np

from blender_checks import image_array, shown_seamless, uv_layer_array  # noqa: F401 (shown_seamless: for the tests)
from seamless_ao.core.ao import shade
from seamless_ao.core.blend import bilinear
from seamless_ao.core.settings import BakeSettings


def surface_samples(mesh, count, seed=0):
    """Area-weighted random surface points of a TriangleMesh, on faces that can be seen.

    Faces lying on another, opposite-facing surface (a block's bottom on a
    floor) are left out: they are never visible, and their AO depends only
    on how a renderer treats exactly coincident surfaces.

    Returns triangle (k,), bary (k, 3), normals (k, 3) (interpolated shading normals, object space).
    """
    rng = np.random.default_rng(seed)
    weight = np.where(mesh.degenerate | hidden_triangles(mesh), 0.0, mesh.triangle_area)
    triangle = rng.choice(len(weight), size=count, p=weight / weight.sum())
    r1, r2 = rng.random(count), rng.random(count)
    s = np.sqrt(r1)
    bary = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)
    normals = np.einsum("kc,kcd->kd", bary, mesh.corner_normals[triangle])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return triangle, bary, normals


def hidden_triangles(mesh, tolerance=1e-6):
    """Triangles whose centre lies on another triangle facing the opposite way."""
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree

    tree = BVHTree.FromPolygons(mesh.positions.tolist(), mesh.triangles.tolist(), all_triangles=True)
    centres = mesh.positions[mesh.triangles].mean(axis=1)
    hidden = np.zeros(len(mesh.triangles), dtype=bool)
    radius = tolerance * mesh.scale
    for index, (centre, normal) in enumerate(zip(centres.tolist(), mesh.triangle_normal.tolist())):
        for _, other_normal, other, _ in tree.find_nearest_range(Vector(centre), radius):
            if other != index and other_normal.dot(Vector(normal)) < -0.99:
                hidden[index] = True
                break
    return hidden


def reference_ao(ob, mesh, triangle, bary, normals, rays=2048, settings=None, batch=256):
    """AO at surface points with many rays (no adaptive stop), same conventions as the bake."""
    import bpy
    from seamless_ao.operators.api import ray_setup

    settings = (settings or BakeSettings()).replace(adaptive=False)
    params, caster, to_ray = ray_setup(ob, mesh, settings, bpy.context.scene,
                                       bpy.context.evaluated_depsgraph_get(), rays=rays)
    try:
        points = np.einsum("kc,kcd->kd", bary, mesh.positions[mesh.triangles[triangle]])
        points, shading = to_ray(points, normals)
        _, geometric = to_ray(points, mesh.triangle_normal[triangle])
        out = np.empty(len(points), dtype=np.float64)
        for start in range(0, len(points), batch):
            part = slice(start, start + batch)
            out[part] = shade(points[part], shading[part], geometric[part],
                              np.arange(len(points))[part] + 7919, params, caster)[0]
        return out
    finally:
        if hasattr(caster, "free"):
            caster.free()


def shown_single_uv(ob, image, uv_name, triangle_loops, triangle, bary):
    """What an Image Texture node (linear) through one UV map shows at the points."""
    loops = triangle_loops[triangle]
    uv = np.einsum("kc,kcd->kd", bary, uv_layer_array(ob.data, uv_name)[loops])
    return bilinear(image_array(image), uv)


def errors(shown, reference):
    """(RMSE, 99th percentile of |error|)."""
    difference = np.abs(np.asarray(shown) - np.asarray(reference))
    return float(np.sqrt(np.mean(difference**2))), float(np.percentile(difference, 99))
