"""Error as the user sees it: the shown AO at random visible surface points against the plain reference."""

import numpy as np

from blender_checks import image_array, shown_seamless, uv_layer_array  # noqa: F401 (shown_seamless: for the tests)
from plain_reference import plain_ao, visible_points
from seamless_ao.core.image.shown import bilinear
from seamless_ao.core.settings import BakeSettings

#: Accuracy the tests hold a bake to, against the plain reference at random visible points: RMSE of the shown AO.
RMSE_LIMIT = 0.03
#: ... and its 99th percentile of the absolute error.
P99_LIMIT = 0.12


def surface_samples(mesh, count, seed=0):
    """Area-weighted random visible surface points of a TriangleMesh.

    Points lying on another, opposite-facing surface (the part of a block's
    bottom on a floor) are left out, each point on its own (see
    :func:`plain_reference.visible_points`): they are never seen, and their
    AO depends only on how a renderer treats exactly coincident surfaces.

    Returns triangle (k,), bary (k, 3), normals (k, 3) (interpolated shading normals, object space).
    """
    triangle, bary, _ = visible_points(mesh.positions, mesh.triangles, count, seed=seed)
    normals = np.einsum("kc,kcd->kd", bary, mesh.corner_normals[triangle])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return triangle, bary, normals


def reference_ao(ob, mesh, triangle, bary, normals, rays=2048, settings=None, seed=0):
    """The plain reference (:mod:`plain_reference`, no code shared with the bake) at surface points.

    The object as it stands in the scene: positions and normals in world
    space (centred on the object), the bake's maximum distance (``settings``, default
    :class:`BakeSettings`: half the world bounding-box diagonal).  Binary
    hits only: the reference knows no falloff, cone, ground plane or scene
    occluders, so it refuses settings that use them.
    """
    settings = settings or BakeSettings()
    if (settings.falloff, settings.cone_angle, settings.use_ground_plane, settings.use_scene_occluders) != (
            "NONE", 90.0, False, False):
        raise ValueError("the plain reference computes binary hemisphere AO of the object alone")
    to_world = world_map(ob)
    world, _ = to_world(mesh.positions)
    # centred in float64 (AO does not move with the object), so a float32 BVH keeps its precision far out
    world -= 0.5 * (world.min(axis=0) + world.max(axis=0))
    points = np.einsum("kc,kcd->kd", bary, world[mesh.triangles[triangle]])
    max_distance = (0.5 * float(np.linalg.norm(world.max(axis=0) - world.min(axis=0)))
                    if settings.auto_distance else settings.max_distance)
    return plain_ao(world, mesh.triangles, points, to_world(points, normals)[1],
                    to_world(points, mesh.triangle_normal[triangle])[1], max_distance, rays=rays, seed=seed)


def world_map(ob):
    """``to_world(points (k, 3), normals (k, 3) or None) -> (points, unit normals)``: object space to
    world space as ``ob`` stands (normals by the inverse transpose, as Blender shows them)."""
    matrix = np.array(ob.matrix_world, dtype=np.float64)
    linear, shift = matrix[:3, :3], matrix[:3, 3]

    def to_world(points, normals=None):
        if normals is None:
            return points @ linear.T + shift, None
        turned = normals @ np.linalg.inv(linear)                             # inverse transpose, as rows
        return points @ linear.T + shift, turned / np.linalg.norm(turned, axis=1, keepdims=True)
    return to_world


def shown_single_uv(ob, image, uv_name, triangle_loops, triangle, bary):
    """What an Image Texture node (linear) through one UV map shows at the points."""
    loops = triangle_loops[triangle]
    uv = np.einsum("kc,kcd->kd", bary, uv_layer_array(ob.data, uv_name)[loops])
    return bilinear(image_array(image), uv)


def errors(shown, reference):
    """(RMSE, 99th percentile of |error|)."""
    difference = np.abs(np.asarray(shown) - np.asarray(reference))
    return float(np.sqrt(np.mean(difference**2))), float(np.percentile(difference, 99))
