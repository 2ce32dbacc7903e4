"""Benchmark: The benchmark meshes: one name, one mesh.

    .venv/5.0/bin/python tests/bench/bench_meshes.py

Builds every mesh the benchmarks name (``tests/bench/report.py``'s ``MESHES``: the report's four are
*suzanne*, *dense*, *scan* and *interior*; then the generated real-asset set of ``tests/support/real_assets.py``
that bench_assets, bench_atlas and bench_memory bake, whose *interior* is the same mesh) as the benchmarks
build them, and counts its triangles (Blender's
loop triangles), its vertices and its pieces: triangles joined through shared corners, vertices at the same
position counting as one (a box with split normals is one piece, not six faces).
Every page that names a mesh means the one in this table.
"""

import numpy as np

from common import finish, markdown_table, say

import bpy

from real_assets import ASSETS
from report import DEFAULT_MESHES, MESHES, fresh
from seamless_ao.core.arrays.graph import connected_components

#: What each mesh is, in a few words.
WHAT = {
    "cube": "Blender's default cube",
    "suzanne": "Blender's Suzanne, subdivided twice, smooth",
    "cornell": "the Cornell box with two blocks (the thesis' test scene)",
    "sphere_plane": "a sphere hovering over a plane",
    "fold": "a spiral ramp folding over itself three times",
    "dense": "Suzanne subdivided four times, smooth",
    "scan": "a scan-like closed noisy surface with holes, smooth (tests/support/real_assets.py)",
    "interior": "a generated interior of many separate pieces (tests/support/real_assets.py)",
    "noisy_scan": "the real-asset set's scan: a larger lumpy closed surface with four holes",
    "chips": "ten thousand tiny tetrahedra scattered in a cube",
    "long_thin": "a beam a thousand times longer than wide, cut into segments",
}


def counts(ob):
    """(triangles, vertices, pieces) of mesh object ``ob``, as Blender triangulates it."""
    mesh = ob.data
    mesh.calc_loop_triangles()
    triangles = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    positions = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", positions)
    return array_counts(positions.reshape(-1, 3), triangles.reshape(-1, 3))


def array_counts(positions, triangles):
    """(triangles, vertices, pieces) of a mesh given as arrays (v, 3) and (t, 3)."""
    _, welded = np.unique(np.asarray(positions, dtype=np.float64), axis=0, return_inverse=True)
    corners = welded.reshape(-1)[np.asarray(triangles)]
    edges = np.concatenate([corners[:, [0, 1]], corners[:, [1, 2]]])
    labels = connected_components(len(positions), edges)
    return len(triangles), len(positions), len(np.unique(labels[corners[:, 0]]))


def main():
    rows = []
    for name in MESHES:
        triangles, vertices, pieces = counts(fresh(name))
        rows.append(["**{}**".format(name) if name in DEFAULT_MESHES else name, WHAT[name],
                     "{:,}".format(triangles), "{:,}".format(vertices), "{:,}".format(pieces)])
    for name, build in ASSETS.items():
        if name not in MESHES:
            triangles, vertices, pieces = array_counts(*build())
            rows.append([name, WHAT[name], "{:,}".format(triangles), "{:,}".format(vertices), "{:,}".format(pieces)])
    say(markdown_table(["name", "what", "triangles", "vertices", "pieces"], rows))
    say()
    say("In bold, the report's four meshes (``report.py``'s default).")


if __name__ == "__main__":
    try:
        main()
    finally:
        finish(__file__, __doc__)
