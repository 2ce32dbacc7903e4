"""Benchmark: The layout on a texel-scale proxy of the mesh against the layout on the mesh itself (issue 56).

    .venv/5.0/bin/python tests/bench/bench_texel_proxy.py [--meshes million_suzanne million_scan dense scan]
        [--image-size 256] [--cells 1 2] [--runs 3]

What a layout whose cost follows the image could gain, before it is built.
Each mesh is read as the bake reads it, and core/layout.py's build_layout
(charts, injectivity, pack, rasterise) runs on it at the image size.  Then
its vertices are clustered in cubes a cell wide (core/mesh/proxy.py, cells
in texels of the mesh's own layout: 1 and 2), the triangles of three
clusters become the proxy's (each set of clusters and winding once, flat
shaded), and build_layout runs on that proxy.  Times are medians of --runs
runs, in one process (the mesh first, then each proxy); the proxy's include
clustering it.  The charts and texels say what the proxy's layout would
hand on: its clustered triangles cross and fold, so it makes many more
charts than the mesh.  No triangle of the mesh is mapped to a proxy chart
here, and nothing is baked: this is the ceiling of that route's layout
stages, not a bake.
"""

import argparse
import statistics
import time

import numpy as np

from common import finish, markdown_table, say

import bench_million
import report
from seamless_ao.core.layout import build_layout
from seamless_ao.core.mesh.proxy import grid_clusters, proxy_triangles
from seamless_ao.core.mesh.triangle_mesh import MeshArrays
from seamless_ao.operators.adapters.mesh_data import read_triangles

STAGES = ("charts", "injectivity", "pack", "rasterise")


def proxy_mesh(mesh, cell):
    """The :class:`TriangleMesh` of ``mesh``'s vertices clustered in cubes ``cell`` wide, flat shaded."""
    cluster, centre = grid_clusters(mesh.positions, cell)
    proxy, _ = proxy_triangles(cluster, mesh.triangles)
    corners = centre[proxy]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    return MeshArrays(centre, proxy, np.arange(len(proxy)), np.repeat(normal[:, None, :], 3, axis=1),
                      face_count=len(proxy)).mesh()


def timed_layouts(make_mesh, image_size, runs):
    """``(median seconds, median stage seconds, last layout, triangles)`` of ``runs`` builds of
    ``make_mesh()`` and its layout."""
    seconds, stages = [], {stage: [] for stage in STAGES}
    for _ in range(runs):
        start = time.perf_counter()
        mesh = make_mesh()
        layout = build_layout(mesh, image_size=image_size)
        seconds.append(time.perf_counter() - start)
        for stage in STAGES:
            stages[stage].append(layout.timings.get(stage, 0.0))
    return (statistics.median(seconds), {stage: statistics.median(values) for stage, values in stages.items()},
            layout, len(mesh.triangles))


def row(name, what, seconds, stages, layout, triangles):
    return [name, what, "{:,}".format(triangles), "{:.2f}".format(seconds),
            " + ".join("{} {:.2f}".format(stage, stages[stage]) for stage in STAGES),
            "{:,}".format(layout.charts.count), "{:,}".format(len(layout.texels))]


def main():
    report.MESHES.update(bench_million.MILLION_MESHES)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=["million_suzanne", "million_scan", "dense", "scan"],
                        choices=list(report.MESHES))
    parser.add_argument("--image-size", type=int, default=256)
    parser.add_argument("--cells", nargs="+", type=float, default=[1.0, 2.0], help="cube sides, in texels")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    rows = []
    for name in args.meshes:
        ob = report.fresh(name)
        mesh, _ = read_triangles(ob.data)
        seconds, stages, layout, triangles = timed_layouts(lambda: mesh, args.image_size, args.runs)
        rows.append(row(name, "the mesh", seconds, stages, layout, triangles))
        print(" | ".join(rows[-1]), flush=True)
        for cell in args.cells:
            result = timed_layouts(lambda: proxy_mesh(mesh, cell / layout.atlas.density), args.image_size, args.runs)
            rows.append(row(name, "proxy, {:g}-texel cubes".format(cell), *result))
            print(" | ".join(rows[-1]), flush=True)
    say("Layout of a {0}² image, median of {1} runs; seconds include making the proxy.".format(
        args.image_size, args.runs))
    say()
    say(markdown_table(["mesh", "laid out", "triangles", "seconds", "stages s", "charts", "texels"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
