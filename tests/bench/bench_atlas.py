"""Benchmark: chart building + packing + rasterising at 1024² and 4096² on a ~100k-triangle mesh.

    .venv/5.0/bin/python tests/bench/bench_atlas.py [--triangles 100000] [--sizes 1024 4096]

Prints time per stage, peak numpy memory and atlas utilisation.
Target (issue 4): rasterising 4096² under 10 s.
"""

import argparse

from common import Stopwatch, markdown_table

from bench_clustering import bumpy_sphere
from seamless_ao.core.mesh import TriangleMesh
from seamless_ao.core.pipeline import build_layout


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, default=100_000)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1024, 4096])
    args = parser.parse_args()
    mesh = TriangleMesh.from_triangles(*bumpy_sphere(args.triangles), smooth=True)
    headers = ["image", "triangles", "charts s", "pack s", "rasterise s", "total s", "peak MB", "utilisation",
               "texels", "density"]
    rows = []
    for size in args.sizes:
        with Stopwatch() as watch:
            layout = build_layout(mesh, image_size=size)
        t = layout.timings
        rows.append([f"{size}²", f"{len(mesh.triangles):,}", f"{t['charts']:.2f}", f"{t['pack']:.2f}",
                     f"{t['rasterise']:.2f}", f"{watch.seconds:.2f}", f"{watch.peak_mb:.0f}",
                     f"{layout.atlas.utilisation:.2f}", f"{len(layout.texels):,}", f"{layout.atlas.density:.0f}"])
        print(markdown_table(headers, rows[-1:]), flush=True)
    print()
    print(markdown_table(headers, rows))


if __name__ == "__main__":
    main()
