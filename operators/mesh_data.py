"""Read Blender meshes into the core's arrays, and write UV maps back."""

import numpy as np

from ..core.mesh import TriangleMesh


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
    mesh.calc_loop_triangles()
    count = len(mesh.loop_triangles)
    positions = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", positions)
    triangles = np.empty(count * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    loops = np.empty(count * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("loops", loops)
    polygon = np.empty(count, dtype=np.int32)
    mesh.loop_triangles.foreach_get("polygon_index", polygon)
    corner_normals = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    if len(mesh.loops):
        mesh.corner_normals.foreach_get("vector", corner_normals)
    loops = loops.reshape(-1, 3).astype(np.int64)
    triangle_mesh = TriangleMesh(
        positions.reshape(-1, 3).astype(np.float64),
        triangles.reshape(-1, 3),
        polygon,
        corner_normals.reshape(-1, 3)[loops] if count else np.zeros((0, 3, 3)),
        face_count=len(mesh.polygons),
    )
    return triangle_mesh, loops
