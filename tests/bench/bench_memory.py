"""Benchmark: The memory estimate against measured peaks.

    .venv/5.0/bin/python tests/bench/bench_memory.py [--cases suzanne interior ...]

Each case bakes in a process of its own (16 rays): the mesh is built, the
process's resident memory noted, the bake run, and the growth of the peak
resident memory over that noted level compared with what the bake estimated
before it started (``core/budget.py``, from triangles, image pixels and
texels).  Prints one table, and which cases the estimate misses by more
than ``TOLERATED`` (it may err high: a bake refused early is better than one
that runs out of memory; erring low is the fault to fix).
"""

import argparse
import sys

from common import child_result, finish, markdown_table, print_result, process_peak_mb, resident_mb, say

#: How far the estimate after layout may stray from the measured peak growth, either way.
TOLERATED = 0.30
CASES = {                     # name: (mesh, image size)
    "suzanne-512": ("suzanne", 512),
    "suzanne-1024": ("suzanne", 1024),
    "interior-1024": ("interior", 1024),
    "noisy_scan-1024": ("noisy_scan", 1024),
    "chips-1024": ("chips", 1024),
    "dense-250k-1024": ("bumpy-250000", 1024),
    "dense-1M-1024": ("bumpy-1000000", 1024),
    "suzanne-2048": ("suzanne", 2048),
}


def measure(mesh_name, image_size):
    """In this process: (estimated MB, measured MB, triangles, texels)."""
    import bpy

    import package
    from bench_clustering import bumpy_sphere
    from blender_scenes import add_object, mesh_from_arrays, suzanne
    from real_assets import ASSETS
    from seamless_ao.core import budget

    bpy.ops.wm.read_factory_settings(use_empty=True)
    package.seamless_ao.register()
    if mesh_name == "suzanne":
        ob = suzanne(2)
    else:
        positions, triangles = (bumpy_sphere(int(mesh_name.split("-")[1])) if mesh_name.startswith("bumpy")
                                else ASSETS[mesh_name]())
        ob = add_object(mesh_name, mesh_from_arrays(mesh_name, positions, triangles))
    estimates = []
    original = budget.check_budget

    def noting(settings, triangles, pixels, texels):
        estimates.append(budget.estimated_bytes(triangles, texels, pixels, settings.caster_name() == "CYCLES") / 2**20)
        return original(settings, triangles, pixels, texels)
    sys.modules["seamless_ao.core.pipeline"].check_budget = noting      # where the bake asks the budget
    before = resident_mb()
    peak_before = process_peak_mb()
    report = package.seamless_ao.bake([ob], image_size=image_size, rays=16)
    peak = process_peak_mb()
    return dict(first_estimate=estimates[0], layout_estimate=estimates[-1], measured=peak - before,
                peak_before=peak_before, before=before, triangles=sum(len(p.polygons) for p in [ob.data]),
                texels=report.texels)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(CASES))
    parser.add_argument("--one", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        print_result(measure(*CASES[args.one]))
        return
    rows, missed = [], []
    for name in args.cases:
        try:
            r = child_result(__file__, "--one", name)
        except RuntimeError as error:
            rows.append([name, "failed: " + str(error).splitlines()[-1], "", "", "", "", ""])
            continue
        rows.append([name, "{:,}".format(r["triangles"]), "{:,}".format(r["texels"]),
                     "{:,.0f}".format(r["first_estimate"]), "{:,.0f}".format(r["layout_estimate"]),
                     "{:,.0f}".format(r["measured"]), "{:+.0%}".format(r["layout_estimate"] / r["measured"] - 1.0)])
        if abs(r["layout_estimate"] / r["measured"] - 1.0) > TOLERATED:
            missed.append("{} ({:+.0%})".format(name, r["layout_estimate"] / r["measured"] - 1.0))
        print(name, r, file=sys.stderr, flush=True)
    say(markdown_table(["case", "faces", "texels", "estimate before layout MB", "estimate after layout MB",
                          "measured peak growth MB", "estimate vs measured"], rows))
    say()
    say("Outside ±{:.0%}: {}.".format(TOLERATED, ", ".join(missed) if missed else "none"))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
