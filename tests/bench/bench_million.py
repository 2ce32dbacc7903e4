"""Benchmark: A 1M-triangle bake: time and peak memory.

    .venv/5.0/bin/python tests/bench/bench_million.py [--triangles 1000000] [--image-size 1024] [--rays 16]

Too slow for the test suite on two cores, so it lives here; it checks what
the tests check for the other hard cases: no exception, no NaN, values in
[0, 1].
"""

import argparse
import time

import numpy as np

from common import finish, process_peak_mb, say

import bpy

import package
from bench_clustering import bumpy_sphere
from blender_checks import image_array, uv_layer_array
from blender_scenes import add_object


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, default=1_000_000)
    parser.add_argument("--image-size", type=int, default=1024)
    parser.add_argument("--rays", type=int, default=16)
    args = parser.parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    package.seamless_ao.register()
    positions, triangles = bumpy_sphere(args.triangles)
    mesh = bpy.data.meshes.new("Million")
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.astype(np.float32).ravel())
    mesh.loops.add(triangles.size)
    mesh.loops.foreach_set("vertex_index", triangles.astype(np.int32).ravel())
    mesh.polygons.add(len(triangles))
    mesh.polygons.foreach_set("loop_start", np.arange(0, triangles.size, 3, dtype=np.int32))
    mesh.update()
    ob = add_object("Million", mesh)
    start = time.perf_counter()
    report = package.seamless_ao.bake([ob], image_size=args.image_size, rays=args.rays)
    seconds = time.perf_counter() - start
    values = image_array(bpy.data.images[report.image])
    finite = np.isfinite(values).all() and all(np.isfinite(uv_layer_array(ob.data, n)).all()
                                               for n in ("AO_X", "AO_Y", "AO_Z"))
    say("{:,} triangles, {}² image, {} rays: {:.1f} s ({}), peak memory {:.0f} MB, finite: {}, range {:.3f}..{:.3f}"
          .format(len(triangles), args.image_size, args.rays, seconds,
                  ", ".join("{} {:.1f} s".format(k, v) for k, v in report.timings.items()), process_peak_mb(),
                  finite, values.min(), values.max()))
    return 0 if finite and 0.0 <= values.min() and values.max() <= 1.0 else 1


if __name__ == "__main__":
    finish(__file__, __doc__, main())
