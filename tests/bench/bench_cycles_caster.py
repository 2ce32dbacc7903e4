"""Benchmark: the Cycles ray caster against the Geometry Nodes caster, through the bake operator.

    .venv/5.0/bin/python tests/bench/bench_cycles_caster.py [--runs 3] [--meshes suzanne scan interior]
        [--settings 256x32 256x64 512x32 512x64 1024x64]

Ray Caster *Cycles* casts each texel's pilot rays and the creases with the
Geometry Nodes Raycast node and hands the remaining rays to Cycles' AO bake
(docs/how-it-works.md, "Who casts the rays").  Each mesh (report.py's own
*suzanne*, *scan* and *interior*: docs/bench/bench_meshes.md) is baked
through the operator at default settings but the caster, image size and rays,
timed as the user waits (warm: one untimed bake with each caster first; the
median of ``--runs``).  Error: RMSE of what the material shows at report.py's
2000 random visible surface points against its plain reference (4096 rays,
tests/support/plain_reference.py, no code shared with either caster; cached
under ``--work-dir`` as report.py caches it).
"""

from common import finish, markdown_table, say

import bpy

from accuracy import errors, shown_seamless
from report import bench_arguments, fresh_with_reference, seamless_bake

#: "<image size>x<rays per texel>": the node casts the first core/rays/cycles_rules.py BULK_PILOT_RAYS rays of each
#: texel, Cycles the rest.  1024x64 is the bake's default.
SETTINGS = ["256x32", "256x64", "512x32", "512x64", "1024x64"]
CASTERS = [("GEOMETRY_NODES", "Geometry Nodes"), ("CYCLES", "Cycles")]


def main():
    args, settings = bench_arguments(__doc__.splitlines()[0], ["suzanne", "scan", "interior"], SETTINGS, runs=3)
    rows = []
    for name in args.meshes:
        ob, loops, (triangle, bary, normals), ref = fresh_with_reference(name, args.work_dir)
        for caster, _ in CASTERS:                                   # warm-up: Cycles' kernels, the node group
            seamless_bake(ob, image_size=256, rays=32, ray_caster=caster)
        for image_size, rays in settings:
            row = [name, "{}², {}".format(image_size, rays)]
            totals = []
            for caster, _ in CASTERS:
                runs = sorted((seamless_bake(ob, image_size=image_size, rays=rays, ray_caster=caster)
                               for _ in range(args.runs)), key=lambda run: run[0])
                seconds, image_name, stages = runs[len(runs) // 2]
                shown = shown_seamless(ob, bpy.data.images[image_name], loops, triangle, bary, normals)
                rmse, _ = errors(shown, ref)
                totals.append(seconds)
                row += ["{:.2f}".format(seconds), "{:.2f}".format(stages["rays"]), "{:.4f}".format(rmse)]
            row.append("{:.2f}".format(totals[0] / totals[1]))
            rows.append(row)
            print(" | ".join(row), flush=True)
    say("Median of {} bakes through the operator; seconds are the whole bake, rays its rays stage (pilot, "
        "creases and Cycles' steps together).".format(args.runs))
    say()
    say(markdown_table(["mesh", "image², rays", "Geometry Nodes s", "its rays s", "its RMSE", "Cycles s",
                        "its rays s", "its RMSE", "speed-up of the bake"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
