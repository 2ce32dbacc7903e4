"""Benchmark: The generated real assets, both bakers.

    .venv/5.0/bin/python tests/bench/bench_assets.py [--assets interior noisy_scan ...]

For each asset of tests/support/real_assets.py (flat shaded, as generated) and the
noisy scan once more shaded smooth: the plain reference (tests/support/plain_reference.py,
4,096 rays at 500 visible points, sharing no code with either baker), then
Cycles (Smart UV Project + "Bake > Ambient Occlusion", 64 samples) and Seamless
AO (32 rays) at 512² and 1024², each timed and measured on what its material
shows at those points.  Prints one table (RMSE, 99th percentile of the absolute
error, seconds of one run, and for Cycles the median triangle's area in its
image: an island under a texel reads texels no triangle covers).  The tests
hold the assets to RMSE 0.03.  This compares accuracy; fair timing (warm-up,
medians) is report.py's.
"""

import argparse
import sys

from common import finish, markdown_table, say

import bpy
import numpy as np

import real_assets  # noqa: E402
from accuracy import errors, shown_seamless, shown_single_uv  # noqa: E402
from blender_checks import uv_layer_array  # noqa: E402
from blender_scenes import add_object, mesh_from_arrays  # noqa: E402
from cycles_baseline import UV_NAME, cycles_ao_bake  # noqa: E402
from plain_reference import reference_at_visible_points  # noqa: E402
from seamless_ao.operators.adapters.mesh_data import read_triangles  # noqa: E402

PACKAGE = sys.modules["seamless_ao"]
SIZES = (512, 1024)
CYCLES_SAMPLES = 64
RAYS = 32
HEADERS = ["asset", "shading", "baker", "image", "seconds", "RMSE", "p99", "Cycles' median triangle (texels)"]


def fresh_object(name, smooth):
    """An empty scene with the add-on registered and the asset as its only object."""
    if hasattr(bpy.types.Scene, "seamless_ao"):
        PACKAGE.unregister()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    PACKAGE.register()
    positions, triangles = real_assets.ASSETS[name]()
    return add_object(name, mesh_from_arrays(name, positions, triangles, smooth=smooth))


def run_case(name, smooth):
    ob = fresh_object(name, smooth)
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals, reference, max_distance = reference_at_visible_points(mesh)
    shading = "smooth" if smooth else "flat"
    rows = []
    for size in SIZES:
        image, unwrap, bake = cycles_ao_bake(ob, size, CYCLES_SAMPLES, max_distance)
        shown = shown_single_uv(ob, image, UV_NAME, loops, triangle, bary)
        rows.append([name, shading, "Cycles, {} samples".format(CYCLES_SAMPLES), "{}²".format(size),
                     unwrap + bake, *errors(shown, reference), median_texels(uv_layer_array(ob.data, UV_NAME), loops, size)])
        bpy.data.images.remove(image)
    for size in SIZES:
        report = PACKAGE.bake([ob], image_size=size, rays=RAYS, auto_distance=False, max_distance=max_distance)
        shown = shown_seamless(ob, bpy.data.images[report.image], loops, triangle, bary, normals)
        rows.append([name, shading, "Seamless AO, {} rays".format(RAYS), "{}²".format(size),
                     report.seconds, *errors(shown, reference), None])
    return [row[:4] + ["{:.2f}".format(row[4]), "{:.4f}".format(row[5]), "{:.4f}".format(row[6]),
                       "-" if row[7] is None else "{:.3g}".format(row[7])] for row in rows]


def median_texels(uv, loops, size):
    """Median area of a triangle in the image, in texels, through one UV map (loops, 2)."""
    corners = uv[loops] * size                                                      # (t, 3, 2)
    edge1, edge2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    return float(np.median(0.5 * np.abs(edge1[:, 0] * edge2[:, 1] - edge1[:, 1] * edge2[:, 0])))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--assets", nargs="*", default=sorted(real_assets.ASSETS))
    args = parser.parse_args()
    cases = [(name, False) for name in args.assets]
    cases += [("noisy_scan", True)] if "noisy_scan" in args.assets else []
    rows = []
    for name, smooth in cases:
        rows += run_case(name, smooth)
        print(markdown_table(HEADERS, rows[-2 * len(SIZES):]), flush=True)
    say()
    say(markdown_table(HEADERS, rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
