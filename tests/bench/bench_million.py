"""Benchmark: A million triangles: time to Cycles' error, peak memory and where the time goes (issue 56).

    .venv/5.0/bin/python tests/bench/bench_million.py [--meshes million_suzanne million_scan] [--runs 3]

Two meshes of about a million triangles: Suzanne subdivided five times, smooth
shaded, and a scan-like mesh (tests/support/real_assets.py's noisy_scan at a
million triangles: noise-displaced, four holes, smooth shaded).  Each is baked
as report.py bakes (through the operators, warm, median of --runs runs, the
error at 2000 visible points against report.py's plain reference): Smart UV
Project + Cycles' AO bake at 256², 512² and 1024² x 16 and 64 samples, and
Seamless AO (Ray Caster Automatic) from its cheapest setting, 256², 1 ray, up.
The scan's noise is report.py's scan's, scaled with the length of a side
(a scanner's noise follows its sampling step).
For each Cycles level issue 56 names (512²/16, 1024²/16, 1024²/64) it sets
Cycles' cheapest setting at least as accurate beside ours.  Issue 56 asks:
our cheapest bake at most 3 s; each level in at most Cycles' time, and in at
most half of it where Cycles needs 5 s or more; a 1024², 16-ray bake's peak
memory at most 1.2 GB (measured in a process of its own: the peak resident
memory of the whole process, Blender, the mesh and the bake together).
"""

import argparse
import pathlib

from common import child_result, finish, markdown_table, print_result, process_peak_mb, resident_mb, say

import report
from quality_promises import cheapest_reaching
from report import (UV_NAME, cycles_ao_bake, cycles_median_bake, errors, fresh, half_diagonal, read_triangles, reference,
                    seamless_bake, seamless_median_bake, shown_seamless, shown_single_uv)

import bpy

#: report.py's scan: 70,000 triangles with noise 0.002. A scanner's noise follows its sampling step, so at a
#: million triangles (sides sqrt(70,000 / 1,000,000) as long) it is that much smaller; at 0.002 it would be a
#: third of a side, and every triangle a spike.
SCAN_NOISE = 0.002 * (70_000 / 1_000_000) ** 0.5


def _million_scan():
    from blender_scenes import add_object, mesh_from_arrays
    from real_assets import noisy_scan
    positions, triangles = noisy_scan(triangles=1_000_000, noise=SCAN_NOISE)
    return add_object("Million Scan", mesh_from_arrays("Million Scan", positions, triangles, smooth=True))


#: The two meshes, as report.py builds its own (a fresh factory scene each).
MILLION_MESHES = {
    "million_suzanne": lambda: report.suzanne(5, name="Million Suzanne"),
    "million_scan": _million_scan,
    "smoke": lambda: report.suzanne(1, name="Smoke"),        # a small stand-in: checks the script, writes no page
}
CYCLES_SETTINGS = [(size, samples) for size in (256, 512, 1024) for samples in (16, 64)]
OUR_SETTINGS = [(256, 1), (256, 2), (256, 4), (256, 8), (512, 8), (512, 16), (512, 32), (1024, 16)]
#: The Cycles settings whose error issue 56 asks us to reach.
LEVELS = [(512, 16), (1024, 16), (1024, 64)]
#: Issue 56's targets.
CHEAPEST_SECONDS = 3.0
HALF_FROM_SECONDS = 5.0
PEAK_MB = 1.2 * 1024
MEMORY_SETTING = (1024, 16)


def bake_mesh(name, cache, runs):
    """Every setting of both bakers on mesh ``name``: ``(triangles, [(baker, size, rays, seconds, RMSE, stages)])``."""
    ob = fresh(name)
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals, ref, seconds = reference(ob, mesh, cache)
    print("{}: {:,} triangles, reference {:.0f} s".format(name, len(mesh.triangles), seconds), flush=True)
    distance = half_diagonal(ob, mesh)
    bpy.data.images.remove(cycles_ao_bake(ob, 256, 1, distance)[0])        # the warm-ups report.py does
    seamless_bake(ob, image_size=256, rays=1)
    seamless_bake(ob, image_size=256, rays=16)
    results = []
    for size, samples in CYCLES_SETTINGS:
        unwrap, bake, image = cycles_median_bake(ob, size, samples, distance, runs)
        rmse = errors(shown_single_uv(ob, image, UV_NAME, loops, triangle, bary), ref)[0]
        results.append(("Cycles", size, samples, unwrap + bake, rmse, "unwrap {:.2f} + bake {:.2f}".format(unwrap, bake)))
        bpy.data.images.remove(image)
        print("  ", results[-1], flush=True)
    for size, rays in OUR_SETTINGS:
        seconds, image_name, stages = seamless_median_bake(ob, runs, image_size=size, rays=rays)
        rmse = errors(shown_seamless(ob, bpy.data.images[image_name], loops, triangle, bary, normals), ref)[0]
        # what the stages leave out: reading the mesh, the casters' setup and writing UV maps, image and materials
        stages = dict(stages, other=seconds - sum(stages.values()))
        results.append(("Seamless AO", size, rays, seconds, rmse,
                        " + ".join("{} {:.2f}".format(k, v) for k, v in stages.items())))
        print("  ", results[-1], flush=True)
    return len(mesh.triangles), results


def level_rows(name, results):
    """Issue 56's table rows for one mesh, and how many of its levels keep the rule."""
    runs = [(r[0] == "Cycles", (r[3], r[4], "{}²/{}".format(r[1], r[2]))) for r in results]    # (seconds, RMSE, label)
    cycles = [run for is_cycles, run in runs if is_cycles]
    seamless = [run for is_cycles, run in runs if not is_cycles]
    rows, kept = [], 0
    for size, samples in LEVELS:
        level = next(rmse for _, rmse, label in cycles if label == "{}²/{}".format(size, samples))
        theirs = cheapest_reaching(cycles, level)
        allowed = theirs[0] * (0.5 if theirs[0] >= HALF_FROM_SECONDS else 1.0)
        ours = cheapest_reaching(seamless, level)
        row = [name, "{}²/{} ({:.4f})".format(size, samples, level), "{:.2f} s ({})".format(theirs[0], theirs[2]),
               "{:.2f} s".format(allowed)]
        if ours is not None:
            keeps = ours[0] <= allowed
            kept += keeps
            row += ["{:.2f} s ({}, {:.4f})".format(ours[0], ours[2], ours[1]), "{:.2f}".format(ours[0] / theirs[0]),
                    "yes" if keeps else "**no**"]
        else:
            row += ["none (best {:.4f})".format(min(rmse for _, rmse, _ in seamless)), "-", "**no**"]
        rows.append(row)
    return rows, kept


def peak_memory(name):
    """In a process of its own: ``{"peak": MB, "before": MB}`` of a MEMORY_SETTING bake of mesh ``name``."""
    try:
        return child_result(__file__, "--memory-of", name)
    except RuntimeError as error:
        raise RuntimeError("the memory run of {} failed: {}".format(name, error)) from None


def measure_memory(name):
    ob = fresh(name)
    before = resident_mb()
    size, rays = MEMORY_SETTING
    seamless_bake(ob, image_size=size, rays=rays)
    print_result({"peak": process_peak_mb(), "before": before})


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=["million_suzanne", "million_scan"], choices=list(MILLION_MESHES))
    parser.add_argument("--runs", type=int, default=3, help="timed runs of each setting (the median counts)")
    parser.add_argument("--work-dir", default="out/bench", help="the reference cache (shared with report.py)")
    parser.add_argument("--memory-of", help=argparse.SUPPRESS)
    args = parser.parse_args()
    report.MESHES.update(MILLION_MESHES)
    if args.memory_of:
        measure_memory(args.memory_of)
        return
    cache = pathlib.Path(args.work_dir).resolve() / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    runs_table, levels_table, summary = [], [], []
    for name in args.meshes:
        triangles, results = bake_mesh(name, cache, args.runs)
        for baker, size, rays, seconds, rmse, stages in results:
            runs_table.append([name, baker, "{}², {} {}".format(size, rays, "samples" if baker == "Cycles" else "rays"),
                               "{:.2f}".format(seconds), stages, "{:.4f}".format(rmse)])
        rows, kept = level_rows(name, results)
        levels_table += rows
        cheapest = next(r for r in results if r[0] != "Cycles" and (r[1], r[2]) == OUR_SETTINGS[0])
        memory = peak_memory(name)
        summary.append("- {}: {:,} triangles. Our cheapest bake ({}², {} ray) takes {:.2f} s (target {:.0f} s: {}). "
                       "{} of {} levels kept. A {}², {}-ray bake peaks at {:,.0f} MB for the whole process, "
                       "{:,.0f} MB of it before the bake (target {:,.0f} MB: {}).".format(
                           name, triangles, OUR_SETTINGS[0][0], OUR_SETTINGS[0][1], cheapest[3], CHEAPEST_SECONDS,
                           "met" if cheapest[3] <= CHEAPEST_SECONDS else "not met", kept, len(LEVELS),
                           *MEMORY_SETTING, memory["peak"], memory["before"], PEAK_MB,
                           "met" if memory["peak"] <= PEAK_MB else "not met"))
    say(markdown_table(["mesh", "baker", "setting", "time s", "stages s", "RMSE"], runs_table))
    say()
    say("Time to each Cycles level issue 56 names: Cycles' cheapest setting at least as accurate, and ours "
        "(allowed: Cycles' time, half of it where Cycles needs {:.0f} s or more).".format(HALF_FROM_SECONDS))
    say()
    say(markdown_table(["mesh", "Cycles level (its RMSE)", "Cycles' cheapest to it", "allowed",
                        "Seamless AO's cheapest (RMSE)", "ratio", "kept"], levels_table))
    say()
    for line in summary:
        say(line)
    return "smoke" in args.meshes


if __name__ == "__main__":
    smoke = main()
    finish(__file__, __doc__, 1 if smoke else 0)          # a smoke run writes no page
