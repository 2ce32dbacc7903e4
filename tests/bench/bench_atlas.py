"""Benchmark: Fixed cost before the first ray, per mesh and image size.

    .venv/5.0/bin/python tests/bench/bench_atlas.py [--sizes 256 512 1024] [--spheres 250000 1000000]

Meshes: the generated real-asset set (tests/support/real_assets.py: interior,
noisy_scan, chips and long_thin, counted in docs/bench/bench_meshes.md) and
bumpy spheres of the given triangle counts.  Prints time per stage, peak numpy
memory, utilisation, texel density and xatlas runs, then whether issue 13's
targets are met: charts + pack + rasterise <= 1.0 s at 250k triangles and
<= 4 s at 1M (timed under tracemalloc, which slows numpy a little).
"""

import argparse
import time

from common import finish, markdown_table, say, Stopwatch

import real_assets  # noqa: E402
from bench_clustering import bumpy_sphere  # noqa: E402
from seamless_ao.core.atlas import packing  # noqa: E402
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh  # noqa: E402
from seamless_ao.core.layout import build_layout  # noqa: E402

#: Issue 13's targets for charts + pack + rasterise (seconds), by triangle count.
TARGETS = {250_000: 1.0, 1_000_000: 4.0}

HEADERS = ["mesh", "triangles", "image", "charts s", "injectivity s", "pack s", "rasterise s", "total s", "peak MB",
           "charts", "utilisation", "density", "xatlas runs", "warnings"]
#: Where the fixed cost goes, for the verdict: column names of the stages.
STAGES = ["charts", "injectivity", "pack", "rasterise"]


def count_runs():
    """Wrap Packer.place to count xatlas runs and time them; returns [runs, seconds]."""
    runs = [0, 0.0]
    place = packing.Packer.place

    def counted(self, *args, **kwargs):
        runs[0] += 1
        start = time.perf_counter()
        try:
            return place(self, *args, **kwargs)
        finally:
            runs[1] += time.perf_counter() - start

    packing.Packer.place = counted
    return runs


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024])
    parser.add_argument("--spheres", type=int, nargs="*", default=[250_000, 1_000_000])
    parser.add_argument("--assets", nargs="*", default=sorted(real_assets.ASSETS))
    args = parser.parse_args()
    runs = count_runs()
    cases = [(name, lambda name=name: real_assets.ASSETS[name](), args.sizes) for name in args.assets]
    cases += [("bumpy sphere", lambda n=n: bumpy_sphere(n), [1024]) for n in args.spheres]
    rows = []
    for name, make, sizes in cases:
        mesh = TriangleMesh.from_triangles(*make(), smooth=True)
        for size in sizes:
            runs[:] = [0, 0.0]
            with Stopwatch() as watch:
                layout = build_layout(mesh, image_size=size)
            t = layout.timings
            rows.append([name, f"{len(mesh.triangles):,}", f"{size}²", *(f"{t[stage]:.2f}" for stage in STAGES),
                         f"{watch.seconds:.2f}", f"{watch.peak_mb:.0f}",
                         f"{layout.charts.count:,}", f"{layout.atlas.utilisation:.2f}", f"{layout.atlas.density:.3g}",
                         "{} ({:.2f} s)".format(runs[0], runs[1]), len(layout.atlas.warnings)])
            print(markdown_table(HEADERS, rows[-1:]), flush=True)
    say()
    say(markdown_table(HEADERS, rows))
    # issue 13's fixed-cost targets: charts + pack + rasterise at 250k and 1M triangles (1024²)
    say()
    for row in rows:
        triangles = int(row[1].replace(",", ""))
        target = TARGETS.get(min(TARGETS, key=lambda n: abs(n - triangles))) if row[0] == "bumpy sphere" else None
        if target is not None:
            total = float(row[7])
            verdict = "met" if total <= target else "missed by {:.1f}x".format(total / target)
            stages = ", ".join("{} {}".format(stage, value) for stage, value in zip(STAGES, row[3:7]))
            say("target: charts + pack + rasterise at {} triangles <= {:.1f} s: {:.2f} s, {} ({} s; xatlas runs "
                  "within pack: {})".format(row[1], target, total, verdict, stages, row[12]))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
