"""Meshes and scenes made with bpy, for tests and benchmarks (the demo's scenes come from the package)."""

import bpy
import numpy as np

import package  # noqa: F401  (imports the add-on as ``seamless_ao``)
from seamless_ao.operators.launchers.demo_scenes import (add_object, cornell_box, demo_scene,  # noqa: F401
                                                           mesh_from_faces, sphere_over_plane, suzanne)


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


