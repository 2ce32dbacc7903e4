"""Benchmark: the Quality presets against Blender's own route, promise by promise.

Each of report.py's four meshes is baked with Cycles at its nine settings (Smart UV Project, then the AO bake)
and with Seamless AO's three Quality presets through the bake operator, both timed as report.py times them
(warm, the median of --runs) and both measured against report.py's reference (cached, shared).  This is
report.py without its sweep of Seamless AO settings and its seam measures: the quick check of what each
preset promises (issue 52).  report.py's page holds the same table.

    .venv/5.0/bin/python tests/bench/bench_quality.py [--meshes suzanne dense scan interior] [--runs 3]
"""

import argparse
import pathlib
import time

import numpy as np

from common import finish, markdown_table, say

import bpy

import report
from accuracy import errors, shown_seamless, shown_single_uv
from cycles_baseline import UV_NAME, cycles_ao_bake
from quality_promises import PRESET_METHOD, promise_sentence, promise_table
from seamless_ao.core.settings import PRESETS, QUALITY_ITEMS
from seamless_ao.operators.adapters.mesh_data import read_triangles


def bake_mesh(name, cache, runs, curves, rows):
    """Cycles' nine settings and the three presets on mesh ``name``, into ``curves`` and ``rows``."""
    ob = report.fresh(name)
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals, ref, _ = report.reference(ob, mesh, cache)
    distance = 0.5 * float(np.linalg.norm(np.ptp(mesh.positions @ np.array(ob.matrix_world)[:3, :3].T, axis=0)))
    bpy.data.images.remove(cycles_ao_bake(ob, 256, 1, distance)[0])      # the same warm-up as report.py's
    report.seamless_bake(ob, image_size=256, rays=1)
    report.seamless_bake(ob, image_size=256, rays=16, ray_caster="CYCLES")
    for size, samples in report.CYCLES_RUNS:
        unwrap, bake, image = report.cycles_median_bake(ob, size, samples, distance, runs)
        rmse = errors(shown_single_uv(ob, image, UV_NAME, loops, triangle, bary), ref)[0]
        curves.setdefault((name, "Cycles"), []).append((unwrap + bake, rmse, "{}/{}".format(size, samples)))
        rows.append([name, "Cycles", "{}², {} samples".format(size, samples), "{:.2f}".format(unwrap + bake),
                     "{:.4f}".format(rmse)])
        bpy.data.images.remove(image)
        print(" | ".join(rows[-1]), flush=True)
    for quality, label, _ in QUALITY_ITEMS:
        if quality not in PRESETS:
            continue
        seconds, image_name, _ = report.seamless_median_bake(ob, runs, quality=quality)
        rmse = errors(shown_seamless(ob, bpy.data.images[image_name], loops, triangle, bary, normals), ref)[0]
        curves.setdefault((name, PRESET_METHOD), []).append((seconds, rmse, label))
        rows.append([name, "Seamless AO", bpy.context.scene.seamless_ao.last_bake_quality, "{:.2f}".format(seconds),
                     "{:.4f}".format(rmse)])
        print(" | ".join(rows[-1]), flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=report.DEFAULT_MESHES, choices=list(report.MESHES))
    parser.add_argument("--runs", type=int, default=3, help="timed runs of each setting (the median is reported)")
    parser.add_argument("--work-dir", default="out/bench", help="the reference cache (shared with report.py)")
    args = parser.parse_args()
    cache = pathlib.Path(args.work_dir).resolve() / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    curves, rows, started = {}, [], time.perf_counter()
    for name in args.meshes:
        bake_mesh(name, cache, args.runs, curves, rows)
    say("Median of {} runs each; total {:.0f} s.".format(args.runs, time.perf_counter() - started))
    say()
    say(markdown_table(["mesh", "baker", "settings", "time s", "RMSE"], rows))
    say()
    table, counts = promise_table(curves)
    say(table)
    say()
    say(promise_sentence(counts))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
