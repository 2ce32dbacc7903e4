"""Benchmark: the layout of many objects baked together into one image (issue 15).

    .venv/5.0/bin/python tests/bench/bench_objects.py [--objects 1000] [--runs 3]

``--objects`` boxes of random proportions (48 triangles each), each in its own
object space as Blender hands them over, laid out together at 1024²
(``core.pipeline.build_layout``).  Prints the median seconds of each stage
over ``--runs`` layouts after an untimed first one.  The objects are
concatenated before clustering (one pass for all), so the per-object Python
overhead of clustering and injectivity is gone.
"""

import argparse
import statistics
import time

from common import markdown_table

import numpy as np

import meshes
import package
from seamless_ao.core.mesh import TriangleMesh
from seamless_ao.core.pipeline import build_layout


def boxes(count, seed=0):
    rng = np.random.default_rng(seed)
    return [TriangleMesh.from_triangles(*meshes.box(size=tuple(rng.uniform(0.2, 1.0, 3)), subdivisions=2))
            for _ in range(count)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args(package.script_arguments())
    parts = boxes(args.objects)
    build_layout(parts, image_size=1024)
    runs = []
    for _ in range(args.runs):
        start = time.perf_counter()
        layout = build_layout(parts, image_size=1024)
        runs.append(dict(layout.timings, total=time.perf_counter() - start))
    stages = list(runs[0])
    print("{} objects, {} triangles, 1024², median of {} runs (seconds)".format(
        len(parts), sum(len(p.triangles) for p in parts), args.runs))
    print(markdown_table(stages, [["{:.3f}".format(statistics.median(r[s] for r in runs)) for s in stages]]))


if __name__ == "__main__":
    main()
    package.hard_exit(0)
