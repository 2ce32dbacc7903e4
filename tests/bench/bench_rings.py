"""Benchmark: Rays for the first padding ring: all, half or none.

    .venv/5.0/bin/python tests/bench/bench_rings.py [--seeds 3]

No point of a chart reads its first padding ring (bilinear filtering reads
covered and near texels), but the denoiser blends the ring into the chart's
rim texels and mip-maps read it. Each mesh (the generated long thin asset
and the interior of tests/support/real_assets.py) is baked through the API
at each setting with the ring's share of rays whole, halved once or twice
(core/rays/targets.py RING_RAY_HALVINGS; never below MIN_SHARED_RAYS) and with
no ring rays at all (the ring filled from its neighbours, as farther rings
are), over ``--seeds`` seeds. Error: RMSE and 99th percentile of what the
node group shows at 1,000 visible points against the plain 4096-ray
reference (tests/support/plain_reference.py, no code shared with the baker),
as tests/blender/test_real_assets.py measures it. Rays: what the bake cast.
Only errors and ray counts are printed, no times: the rays left out are the
time saved.
"""

import argparse
import functools

import numpy as np

from common import finish, markdown_table, say

import bpy

import package
from accuracy import errors, shown_seamless
from bench_assets import fresh_object
from plain_reference import reference_at_visible_points
from seamless_ao.core import pipeline
from seamless_ao.core.rays import targets
from seamless_ao.operators.adapters.mesh_data import read_triangles

#: (mesh, image size, rays) baked.
CASES = [("long_thin", 512, 32), ("long_thin", 1024, 32), ("interior", 256, 16), ("interior", 512, 16)]
#: (label, padding rings with rays, halvings of the ring's share)
RING_SETTINGS = [("whole", 1, 0), ("half", 1, 1), ("quarter", 1, 2), ("none", 0, 0)]


def bake_with_rings(ob, rings, halvings, **settings):
    """A bake with ``rings`` padding rings given rays, their share halved ``halvings`` times."""
    original = (pipeline.TexelTargets, targets.RING_RAY_HALVINGS)
    pipeline.TexelTargets = functools.partial(targets.TexelTargets, ray_rings=rings)
    targets.RING_RAY_HALVINGS = halvings
    try:
        return package.seamless_ao.bake([ob], **settings)
    finally:
        pipeline.TexelTargets, targets.RING_RAY_HALVINGS = original


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    rows = []
    for name in dict.fromkeys(case[0] for case in CASES):
        ob = fresh_object(name, smooth=False)
        mesh, loops = read_triangles(ob.data)
        triangle, bary, normals, reference, max_distance = reference_at_visible_points(mesh, count=1000)
        for _, size, rays in (case for case in CASES if case[0] == name):
            whole_rays = None
            for label, rings, halvings in RING_SETTINGS:
                rmse, p99, cast = [], [], []
                for seed in range(args.seeds):
                    report = bake_with_rings(ob, rings, halvings, image_size=size, rays=rays, seed=seed,
                                             auto_distance=False, max_distance=max_distance)
                    shown = shown_seamless(ob, bpy.data.images[report.image], loops, triangle, bary, normals)
                    rmse_one, p99_one = errors(shown, reference)
                    rmse.append(rmse_one)
                    p99.append(p99_one)
                    cast.append(report.rays)
                whole_rays = whole_rays or np.mean(cast)
                rows.append([name, "{}², {}".format(size, rays), label, "{:,.0f}".format(np.mean(cast)),
                             "{:.0%}".format(np.mean(cast) / whole_rays), "{:.4f}".format(np.mean(rmse)),
                             "{:.4f}".format(np.mean(p99))])
                print(rows[-1], flush=True)
    say("Mean over {} seeds; rays cast as a share of the bake with the whole ring.".format(args.seeds))
    say()
    say(markdown_table(["mesh", "image², rays", "ring's rays", "rays cast", "of whole", "RMSE", "p99"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
