"""Would Cycles cast our rays faster? Cycles' AO at our own texels against the Geometry Nodes caster

Issue 30 asks whether Cycles (Embree) should be an optional ray engine, if it is faster at equal error.
Cycles has no call that casts given rays, so the one route is a bake: a mesh of one tiny triangle per
texel (the texel's lifted surface point, its shading normal as a custom normal, a UV triangle around a
pixel of its own), invisible to every ray kind, baked with "Bake > Ambient Occlusion" into a float
image while the object is the occluder. This is what the Cycles ray caster does
(operators/adapters/cycles_caster.py, ``CyclesCaster.ambient_occlusion``), which this script calls:
in a temporary scene, with no bounces, adaptive sampling or denoising, the same maximum distance, and
no surface shader.

Both routes shade the same texels of one Seamless AO layout at 256² with the same number of rays per
texel, without adaptive stopping, weighted rays or denoising. Time: Seamless AO's rays stage (as the
bake reports it, BVH build and crease pass included) against the whole ``ambient_occlusion`` call
(the texel mesh, scene sync, BVH build and reading the image back included), median of the runs. Error: at random covered
texels that no piece buries, against the plain reference (tests/support/plain_reference.py, mathutils'
BVH, no code shared with either route) at the same points and normals.
"""

import argparse
import time

import numpy as np

from common import finish, markdown_table, say

from bench_fixed_cost import scene
from plain_reference import hidden, plain_ao
from seamless_ao.core.mesh.extent import mesh_size
from seamless_ao.core.pipeline import bake_arrays
from seamless_ao.core.atlas.raster import COVERED, texel_geometry
from seamless_ao.core.rays.ray_setup import ORIGIN_OFFSET, AOParams
from seamless_ao.operators.adapters.casters import NodesCaster
from seamless_ao.operators.adapters.casters import CyclesCaster
from seamless_ao.operators.adapters.mesh_data import read_triangles


def cycles_texel_ao(mesh, points, shading, geometric, samples, diagonal, runs):
    """Cycles' AO at the texels through the Cycles caster's own ``ambient_occlusion`` (the mesh as the
    occluder, rays reaching half the object's ``diagonal``): (values (k,), median seconds of the call)."""
    caster = CyclesCaster(mesh.positions, mesh.triangles)
    params = AOParams(rays=samples, max_distance=0.5 * diagonal, offset=ORIGIN_OFFSET * diagonal)
    try:
        seconds = []
        for _ in range(runs):
            start = time.perf_counter()
            values = caster.ambient_occlusion(points, shading, geometric, samples, params)
            seconds.append(time.perf_counter() - start)
    finally:
        caster.free()
    return values, float(np.median(seconds))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--rays", type=int, nargs="+", default=[16, 64])
    parser.add_argument("--points", type=int, default=600, help="texels the reference is computed at")
    parser.add_argument("--reference-rays", type=int, default=2048)
    args = parser.parse_args()
    rows = []
    for name in ("Suzanne", "scan", "interior"):
        ob = scene(name)
        mesh, _ = read_triangles(ob.data)
        diagonal = mesh_size(mesh.positions)
        reference = None
        for rays in args.rays:
            ours, seconds = [], []
            for _ in range(args.runs):
                result = bake_arrays(mesh, make_caster=NodesCaster, image_size=args.size, rays=rays, adaptive=False,
                                     weighted_rays=False, denoise=False)
                seconds.append(result.timings["rays"])
            layout = result.layout
            texels = layout.texels
            cast = np.flatnonzero(result.computed)
            points, shading, geometric = texel_geometry(texels, layout.atlas, layout.mesh, cast)
            if reference is None:
                # the texels are the same at every ray count (the layout does not depend on it)
                # covered texels at points a viewer can see: a texel whose own point lies inside another
                # piece is shaded at the crease instead (core/rays/job.py), which the reference cannot know
                judged = np.flatnonzero((texels.kind[cast] == COVERED) & ~result.buried[cast])
                judged = np.random.default_rng(7).choice(judged, min(2 * args.points, len(judged)), replace=False)
                triangle = layout.atlas.member_triangle[texels.member[cast[judged]]]
                seen = ~hidden(mesh.positions, mesh.triangles, triangle, points[judged])
                judged = np.sort(judged[seen][:args.points])
                reference = plain_ao(mesh.positions, mesh.triangles, points[judged], shading[judged],
                                     geometric[judged], 0.5 * diagonal, rays=args.reference_rays)
                reference_noise = float(np.sqrt(np.mean(reference * (1 - reference)) / args.reference_rays))
            ours_error = result.texel_ao[cast][judged] - reference
            rows.append([name, "Seamless AO, Geometry Nodes", rays, "{:,}".format(len(cast)),
                         "{:.2f}".format(np.median(seconds)),
                         "{:.2f}".format(result.rays / np.median(seconds) / 1e6),
                         "{:.4f}".format(np.sqrt(np.mean(ours_error ** 2))), "{:+.4f}".format(ours_error.mean()), ""])
            print(rows[-1], flush=True)
            values, bake_seconds = cycles_texel_ao(mesh, points, shading, geometric, rays, diagonal, args.runs)
            cycles_error = values[judged] - reference
            rows.append([name, "Cycles at the same texels", rays, "{:,}".format(len(cast)),
                         "{:.2f}".format(bake_seconds), "{:.2f}".format(len(cast) * rays / bake_seconds / 1e6),
                         "{:.4f}".format(np.sqrt(np.mean(cycles_error ** 2))),
                         "{:+.4f}".format(cycles_error.mean()), "{:.1f}".format(np.median(seconds) / bake_seconds)])
            print(rows[-1], "reference noise", reference_noise, flush=True)
    say("At {}², median of {} runs; error at {} covered texels per mesh against {} reference rays each "
        "(the reference's own noise is about {:.3f} RMS on the last mesh).".format(
            args.size, args.runs, args.points, args.reference_rays, reference_noise))
    say()
    say(markdown_table(["mesh", "route", "rays per texel", "texels", "seconds", "M rays/s", "RMSE", "mean error",
                        "Cycles' speed-up"],
                       rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
