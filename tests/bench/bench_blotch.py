"""Benchmark: Low-frequency error (blotches) on a flat wall.

    .venv/5.0/bin/python tests/bench/bench_blotch.py [--size 512] [--grid 48]

The Cornell box's back wall (2 x 2 units, no block near it) sampled on a
``--grid`` x ``--grid`` lattice; the plain reference (tests/support/plain_reference.py,
4096 rays) at each point; then what each bake shows there.  For each bake:
the RMSE of the error, and the RMSE of the error after a box blur of 3 x 3
lattice points (printed in texels of the bake), which keeps only its
low-frequency part: noise that a denoiser turns into blotches shows up there,
and it must fall with more rays as the raw error does.  Seamless AO bakes with
each ray caster (Geometry Nodes, the default, and Cycles, whose own sample
pattern the denoiser then smooths).  The reference's own
noise is in both (about 0.008 raw at 4096 rays, a third of that blurred).
"""

import argparse

from common import finish, markdown_table, say

import bpy
import numpy as np

import package
from accuracy import shown_seamless, shown_single_uv
from blender_scenes import cornell_box
from cycles_baseline import UV_NAME, cycles_ao_bake
from plain_reference import locate, plain_ao
from seamless_ao.operators.adapters.mesh_data import read_triangles

MAX_DISTANCE = 1.7


def blurred(field):
    """3 x 3 box mean of a (n, n) field, over the points that have all eight neighbours: (n-2, n-2)."""
    n = field.shape[0]
    return sum(field[1 + dy:n - 1 + dy, 1 + dx:n - 1 + dx] for dy in (-1, 0, 1) for dx in (-1, 0, 1)) / 9.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--grid", type=int, default=48)
    args = parser.parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    package.seamless_ao.register()
    ob = cornell_box()
    mesh, loops = read_triangles(ob.data)
    xs = np.linspace(-0.9, 0.9, args.grid)
    zs = np.linspace(0.1, 1.9, args.grid)
    X, Z = np.meshgrid(xs, zs)
    points = np.stack([X.ravel(), np.ones(X.size), Z.ravel()], axis=1)             # on the back wall, y = 1
    triangle, bary = locate(mesh.positions, mesh.triangles, points)
    normals = np.einsum("kc,kcd->kd", bary, mesh.corner_normals[triangle])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    assert np.allclose(normals, [0.0, -1.0, 0.0], atol=1e-6), "not all points on the back wall"
    reference = plain_ao(mesh.positions, mesh.triangles, points, normals, mesh.triangle_normal[triangle],
                         MAX_DISTANCE, rays=4096, seed=11)
    spacing = xs[1] - xs[0]
    rows = []

    def row(label, shown, density):
        error = (shown - reference).reshape(args.grid, args.grid)
        rows.append([label, "{:.4f}".format(np.sqrt(np.mean(error**2))),
                     "{:.4f}".format(np.sqrt(np.mean(blurred(error)**2))),
                     "{:.4f}".format(float(np.mean(error))),
                     "-" if density is None else "{:.1f}".format(3 * spacing * density)])

    runs = [(rays, denoise, caster) for caster, ray_counts in (("GEOMETRY_NODES", (8, 32, 128)), ("CYCLES", (32, 128)))
            for denoise in (True, False) for rays in ray_counts]
    for rays, denoise, caster in runs:
        report = package.seamless_ao.bake([ob], image_size=args.size, rays=rays, denoise=denoise, ray_caster=caster,
                                          auto_distance=False, max_distance=MAX_DISTANCE)
        shown = shown_seamless(ob, bpy.data.images[report.image], loops, triangle, bary, normals)
        row("Seamless AO{}, {} rays{}".format(", Cycles rays" if caster == "CYCLES" else "", rays,
                                              "" if denoise else ", no denoise"), shown, report.density)
    for samples in (16, 64, 256):
        image, _, _ = cycles_ao_bake(ob, args.size, samples, MAX_DISTANCE)
        shown = shown_single_uv(ob, image, UV_NAME, loops, triangle, bary)
        row("Cycles, {} samples".format(samples), shown, None)
        bpy.data.images.remove(image)
    say(markdown_table(["bake ({}², back wall of the Cornell box)".format(args.size), "RMSE",
                          "RMSE after 3x3 blur", "mean error", "blur width (texels)"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
