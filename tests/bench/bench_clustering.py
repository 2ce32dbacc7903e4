"""Benchmark: Adjacency and clustering, 10k to 1M triangles.

    .venv/5.0/bin/python tests/bench/bench_clustering.py [--sizes 10000 100000 1000000]

Prints triangles per second and peak numpy memory (tracemalloc) per size.
Target (issue 3): 1M triangles under 10 s and 2 GB on a 2-core machine, near-linear growth.
"""

import argparse

import numpy as np

from common import finish, markdown_table, say, Stopwatch

from seamless_ao.core.mesh.adjacency import face_adjacency
from seamless_ao.core.charts.clustering import cluster_faces
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh


def bumpy_sphere(triangles):
    """A closed sphere with bumps (varied normals, many charts), about ``triangles`` triangles."""
    segments = int(np.sqrt(triangles))
    rings = max(3, triangles // (2 * segments))
    theta = np.linspace(0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    radius = 1.0 + 0.08 * np.sin(9 * t) * np.sin(7 * p)
    body = np.stack([radius * np.sin(t) * np.cos(p), radius * np.sin(t) * np.sin(p), radius * np.cos(t)], -1)
    positions = np.vstack([body.reshape(-1, 3), [[0, 0, 1.0], [0, 0, -1.0]]])
    r, c = np.meshgrid(np.arange(rings - 2), np.arange(segments), indexing="ij")
    a, b = r * segments + c, r * segments + (c + 1) % segments
    d, e = a + segments, b + segments
    quads = np.concatenate([np.stack([a, e, b], -1).reshape(-1, 3), np.stack([a, d, e], -1).reshape(-1, 3)])
    k = np.arange(segments)
    top, bottom, last = len(body.reshape(-1, 3)), len(body.reshape(-1, 3)) + 1, (rings - 2) * segments
    caps = np.concatenate([np.stack([np.full(segments, top), (k + 1) % segments, k], -1),
                           np.stack([np.full(segments, bottom), last + k, last + (k + 1) % segments], -1)])
    return positions, np.vstack([quads, caps])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    args = parser.parse_args()
    rows = []
    for size in args.sizes:
        positions, triangles = bumpy_sphere(size)
        mesh = TriangleMesh.from_triangles(positions, triangles, smooth=True)
        with Stopwatch() as adjacency_time:
            topology = face_adjacency(mesh)
        with Stopwatch() as cluster_time:
            charts = cluster_faces(mesh, topology)
        total = adjacency_time.seconds + cluster_time.seconds
        rows.append([
            f"{len(triangles):,}", f"{adjacency_time.seconds:.2f}", f"{cluster_time.seconds:.2f}", f"{total:.2f}",
            f"{len(triangles) / total:,.0f}", f"{max(adjacency_time.peak_mb, cluster_time.peak_mb):.0f}",
            charts.count, charts.splits])
        print(markdown_table(
            ["triangles", "adjacency s", "clustering s", "total s", "triangles/s", "peak MB", "charts", "splits"],
            rows[-1:]), flush=True)
    say()
    say(markdown_table(
        ["triangles", "adjacency s", "clustering s", "total s", "triangles/s", "peak MB", "charts", "splits"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
