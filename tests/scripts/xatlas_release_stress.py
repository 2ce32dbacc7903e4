"""Packs many tiny atlases with xatlas while other processes keep every core busy, and says whether letting
go of an atlas hung (core/atlas/settled_atlas.py explains the hang and the wait that avoids it).

    .venv/5.0/bin/python tests/scripts/xatlas_release_stress.py [--packs 150000] [--hogs 3] [--plain]

Each pack is a new ``xatlas.Atlas`` with ten triangles, packed and let go of: through ``settled_atlas`` by
default, directly with ``--plain``.  A pack that has not finished after ``--stall`` seconds is a hang: the
script prints where it stood and exits with status 1.  On a 2-core machine with three busy processes, without
the wait 2 of 2 runs of 150,000 packs hung (and an earlier version of this loop hung in 3 of 4 such runs, in none
of 3 runs of 30,000); with it, a run of 150,000 did not (450 s: the wait lets each atlas's worker, preempted by
the busy processes, reach its sleep first).
"""

import argparse
import contextlib
import faulthandler
import os
import pathlib
import subprocess
import sys
import time

import numpy as np
import xatlas

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "support"))
import package  # noqa: E402,F401  (the add-on as ``seamless_ao``)
from seamless_ao.core.atlas.settled_atlas import settled_atlas  # noqa: E402

#: A Python process that keeps one core busy while its parent lives (a hang ends this one with os._exit).
HOG = "import os, sys\nparent = int(sys.argv[1])\nwhile os.getppid() == parent:\n    pass\n"


def pack_once(settled, vertices, triangles, chart):
    options = xatlas.PackOptions()
    options.padding, options.resolution, options.texels_per_unit = 2, 64, 1.0
    with settled_atlas() if settled else contextlib.nullcontext(xatlas.Atlas()) as atlas:
        atlas.add_uv_mesh(vertices, triangles, chart)
        atlas.generate(xatlas.ChartOptions(), options)
    del atlas


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packs", type=int, default=150_000)
    parser.add_argument("--hogs", type=int, default=3, help="busy processes alongside")
    parser.add_argument("--plain", action="store_true", help="let go of each atlas at once, without the wait")
    parser.add_argument("--stall", type=float, default=10.0, help="seconds without a finished pack that count as a hang")
    args = parser.parse_args()
    vertices = np.random.default_rng(0).random((30, 2)).astype(np.float32) * 10
    triangles = np.arange(30, dtype=np.uint32).reshape(10, 3)
    chart = np.arange(10, dtype=np.uint32)[:, None]
    hogs = [subprocess.Popen([sys.executable, "-c", HOG, str(os.getpid())]) for _ in range(args.hogs)]
    start = time.perf_counter()
    try:
        for index in range(args.packs):
            if index % 100 == 0:
                # a hang leaves faulthandler to print the stack and end the process (status 1)
                faulthandler.dump_traceback_later(args.stall, exit=True)
            pack_once(not args.plain, vertices, triangles, chart)
        faulthandler.cancel_dump_traceback_later()
    finally:
        for hog in hogs:
            hog.kill()
    print("{:,} packs ({}) with {} busy processes: no hang, {:.1f} s".format(
        args.packs, "plain" if args.plain else "settled", args.hogs, time.perf_counter() - start))


if __name__ == "__main__":
    main()
