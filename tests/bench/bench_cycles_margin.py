"""Benchmark: The Smart UV Project island margin that gives Cycles its best chance.

    .venv/5.0/bin/python tests/bench/bench_cycles_margin.py [--margins 1.536 2 4] [--size 512] [--samples 64]

Bakes Suzanne (subdivided twice) and the interior (docs/bench/bench_meshes.md) of
tests/support/real_assets.py with Cycles at one size and sample count, for several
island margins given in texels of that image, and prints the RMSE and 99th
percentile against the plain reference at 1,000 visible points.  Too small a
margin lets a lookup at an island's border read its neighbour; too large
shrinks every island.  report.py uses cycles_baseline.ISLAND_MARGIN_TEXELS.
"""

import argparse

from common import finish, markdown_table, say

import bpy
import numpy as np

import cycles_baseline  # noqa: E402
import real_assets  # noqa: E402
from accuracy import errors, reference_ao, shown_single_uv, surface_samples  # noqa: E402
from blender_scenes import add_object, mesh_from_arrays, suzanne  # noqa: E402
from seamless_ao.operators.adapters.mesh_data import read_triangles  # noqa: E402

MESHES = {
    "suzanne": lambda: suzanne(2),
    "interior": lambda: add_object("Interior", mesh_from_arrays("Interior", *real_assets.interior())),
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--margins", type=float, nargs="+", default=[1.536, 2.0, 4.0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--samples", type=int, default=64)
    args = parser.parse_args()
    rows = []
    for name, make in MESHES.items():
        bpy.ops.wm.read_factory_settings(use_empty=True)
        ob = make()
        bpy.context.view_layer.update()
        mesh, loops = read_triangles(ob.data)
        triangle, bary, normals = surface_samples(mesh, 1000, seed=5)
        reference = reference_ao(ob, mesh, triangle, bary, normals, rays=4096)
        distance = 0.5 * float(np.linalg.norm(np.ptp(mesh.positions, axis=0)))
        for texels in args.margins:
            cycles_baseline.ISLAND_MARGIN_TEXELS = texels
            image, unwrap, bake = cycles_baseline.cycles_ao_bake(ob, args.size, args.samples, distance)
            rmse, p99 = errors(shown_single_uv(ob, image, cycles_baseline.UV_NAME, loops, triangle, bary), reference)
            rows.append([name, "{:g}".format(texels), "{:.4f}".format(texels / args.size), "{:.4f}".format(rmse),
                         "{:.4f}".format(p99)])
            print(markdown_table(["mesh", "margin (texels)", "island_margin", "RMSE", "p99"], rows[-1:]), flush=True)
            bpy.data.images.remove(image)
    say()
    say("Cycles {}², {} samples".format(args.size, args.samples))
    say(markdown_table(["mesh", "margin (texels)", "island_margin", "RMSE", "p99"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
