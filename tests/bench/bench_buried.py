"""Benchmark: Texels buried inside another piece, shaded at the crease or not.

    .venv/5.0/bin/python tests/bench/bench_buried.py [--meshes suzanne dense interior cornell]

Bakes each mesh twice with the same rays: as the add-on does, and with no
texel taken for buried (``core.rays.ao.buried_by_vote`` answering "none", which is the
bake as it was before buried texels: the same rays, the same denoiser, no
crease pass).  Each is evaluated as the shader shows it against the plain
reference at the report's 2000 visible points (``report.py``, cached in
``out/bench/cache``).  Then a box pushed into another (``meshes.pierced_box``,
the hard-case test's mesh) at visible points within a texel of the
intersection.  Accuracy only: one bake per row (a bake repeats itself but for
the Cycles caster's batches, which follow the machine's load:
docs/how-it-works.md).
"""

import argparse
import pathlib
from unittest import mock

import numpy as np

import report
from common import finish, markdown_table, say

import bpy

import meshes
from accuracy import errors, reference_ao, shown_seamless, surface_samples
from blender_scenes import add_object, mesh_from_arrays
from seamless_ao.core.rays import job
from seamless_ao.operators.adapters.mesh_data import read_triangles

CACHE = pathlib.Path(__file__).resolve().parent.parent.parent / "out" / "bench" / "cache"


def nothing_buried(behind, rays, params):
    return np.zeros(np.shape(behind), dtype=bool)


def both_ways(bake):
    """``bake()`` as the add-on does it, then with no texel buried."""
    ours = bake()
    with mock.patch.object(job, "buried_by_vote", nothing_buried):
        plain = bake()
    return ours, plain


def report_mesh(name, size, rays):
    ob = report.fresh(name)
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals, reference, _ = report.reference(ob, mesh, CACHE)

    def bake():
        result = report.PACKAGE.bake([ob], image_size=size, rays=rays)
        return errors(shown_seamless(ob, bpy.data.images[result.image], loops, triangle, bary, normals), reference)

    return both_ways(bake)


def pierced_box(size=256, rays=64):
    """RMSE and most negative error at visible points within a texel of the intersection."""
    report.fresh("cube")
    bpy.data.objects.remove(bpy.data.objects[0])
    positions, triangles, gap = meshes.pierced_box()
    ob = add_object("Pierced", mesh_from_arrays("Pierced", positions, triangles))
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals = surface_samples(mesh, 20000, seed=2)
    points = np.einsum("kc,kcd->kd", bary, mesh.positions[mesh.triangles[triangle]])
    cache = {}

    def bake():
        result = report.PACKAGE.bake([ob], image_size=size, rays=rays)
        near = np.flatnonzero(gap(points) < 1.0 / result.density)
        if "reference" not in cache:
            cache["reference"] = reference_ao(ob, mesh, triangle[near], bary[near], normals[near], rays=1024)
        shown = shown_seamless(ob, bpy.data.images[result.image], loops, triangle[near], bary[near], normals[near])
        return errors(shown, cache["reference"])[0], float((shown - cache["reference"]).min()), len(near)

    return both_ways(bake)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=["suzanne", "dense", "interior", "cornell"])
    parser.add_argument("--image-size", type=int, default=512)
    parser.add_argument("--rays", type=int, default=16)
    args = parser.parse_args(report.package.script_arguments())
    CACHE.mkdir(parents=True, exist_ok=True)
    rows = []
    for name in args.meshes:
        (rmse, p99), (plain_rmse, plain_p99) = report_mesh(name, args.image_size, args.rays)
        rows.append([name, "{}², {} rays".format(args.image_size, args.rays), "{:.4f} / {:.4f}".format(plain_rmse, plain_p99),
                     "{:.4f} / {:.4f}".format(rmse, p99)])
        print(" | ".join(rows[-1]), flush=True)
    (rmse, low, count), (plain_rmse, plain_low, _) = pierced_box()
    rows.append(["pierced box, {} points within a texel of the intersection".format(count), "256², 64 rays",
                 "{:.4f} / min {:+.3f}".format(plain_rmse, plain_low), "{:.4f} / min {:+.3f}".format(rmse, low)])
    say(markdown_table(["mesh", "bake", "no texel buried: RMSE / p99", "buried texels shaded at the crease"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
