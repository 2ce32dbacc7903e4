"""Benchmark: the denoiser's distance weight widened for bakes of few rays, against the fixed one-texel width.

    .venv/5.0/bin/python tests/bench/bench_denoise.py [--meshes suzanne dense scan interior]
        [--settings 256x1 256x2 256x4 256x8 512x1 512x2 512x4 512x8 1024x2]

The denoiser (core/image/denoise.py) weighs a texel's neighbours by a Gaussian of
their 3D distance.  It was one texel wide at every ray count; it now widens
as the rays per texel get fewer (``space_sigma_for``: 2.8 texels at one ray,
1.4 at four, one texel from eight on), in a window of at most three texels
each side.  Each of report.py's meshes is baked through the operator at
default settings but image size and rays, with the Geometry Nodes caster (the
one Ray Caster Automatic takes at 4 rays or fewer), once with the widened
weight and once with the old fixed one (radius 2, one texel: the denoiser's
arguments, patched in for this run only).  Error: RMSE and 99th percentile of
what the material shows at report.py's 2000 random visible surface points
against its plain reference (4096 rays, tests/support/plain_reference.py, no
code shared with the baker; cached under ``--work-dir`` as report.py caches it).
The bake is seeded, so both runs of a setting cast the same rays: only the
filter differs.  Denoise seconds are the bake report's stage, one bake each.
"""

import functools

from common import finish, markdown_table, say

import bpy

from accuracy import errors, shown_seamless
from report import bench_arguments, fresh_with_reference, seamless_bake
from seamless_ao.core.image import denoise as denoise_module
from seamless_ao.core import pipeline

#: "<image size>x<rays per texel>"; from 8 rays on both filters are the same.
SETTINGS = ["256x1", "256x2", "256x4", "256x8", "512x1", "512x2", "512x4", "512x8", "1024x2"]
#: The denoiser before the width followed the rays: radius 2, one texel wide at every ray count.
FIXED = {"radius": 2, "space_sigma": 1.0}


def bake_with(ob, loops, samples, reference_values, image_size, rays, fixed):
    """``(RMSE, p99, denoise seconds)`` of one bake, with the fixed filter or the default one."""
    chosen = denoise_module.denoise
    pipeline.denoise = functools.partial(chosen, **FIXED) if fixed else chosen
    try:
        _, image_name, stages = seamless_bake(ob, image_size=image_size, rays=rays, ray_caster="GEOMETRY_NODES")
    finally:
        pipeline.denoise = chosen
    shown = shown_seamless(ob, bpy.data.images[image_name], loops, *samples)
    rmse, p99 = errors(shown, reference_values)
    return rmse, p99, stages.get("denoise", 0.0)


def main():
    args, settings = bench_arguments(__doc__.splitlines()[0], ["suzanne", "dense", "scan", "interior"], SETTINGS)
    rows = []
    for name in args.meshes:
        ob, loops, samples, ref = fresh_with_reference(name, args.work_dir)
        seamless_bake(ob, image_size=256, rays=4, ray_caster="GEOMETRY_NODES")       # warm-up: the node group
        for image_size, rays in settings:
            sigma = denoise_module.space_sigma_for(rays)
            fixed = bake_with(ob, loops, samples, ref, image_size, rays, fixed=True)
            widened = bake_with(ob, loops, samples, ref, image_size, rays, fixed=False)
            row = [name, "{}², {}".format(image_size, rays),
                   "{:.2f} / {}".format(sigma, denoise_module.window_radius(sigma)),
                   "{:.4f} / {:.4f}".format(fixed[0], widened[0]), "{:+.0%}".format(widened[0] / fixed[0] - 1),
                   "{:.3f} / {:.3f}".format(fixed[1], widened[1]), "{:.2f} / {:.2f}".format(fixed[2], widened[2])]
            rows.append(row)
            print(" | ".join(row), flush=True)
    say("Each cell is fixed / widened: the one-texel weight in a 5x5 window, and the weight as wide as the rays "
        "ask for (width in texels / window radius). One bake each, Geometry Nodes caster, seeded.")
    say()
    say(markdown_table(["mesh", "image², rays", "width / radius", "RMSE", "change", "p99 error",
                        "denoise s"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
