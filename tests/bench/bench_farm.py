"""Benchmark: A folder of assets on a Dask cluster.

    .venv/5.0/bin/python tests/bench/bench_farm.py [--assets 8] [--runs 3] [--workers 1 2 4]

The folder of bench_batch (subdivided Suzanne on a floor slab, about 16k
triangles each, as GLB), baked at 512², 32 rays with ``--force`` through
``batch --scheduler``: a Dask scheduler and 1, 2 or 4 workers (one thread
each) started on the loopback address for each row (tests/support/dask_cluster.py,
the farm tests' own), the workers baking with this Python's ``bpy`` module.
The last row is the local batch, ``--jobs 2``, on the same folder. Each row:
median wall seconds of ``--runs`` batches after one untimed warm-up batch on
that cluster, seconds per asset, and the speed-up over one worker. This
machine has two cores: every worker and every bake shares them, so more than
two workers can only wait for each other here; on a farm each worker is a
machine of its own.
"""

import argparse
import pathlib
import statistics
import sys
import tempfile
import time

from bench_batch import SETTINGS, make_assets
from common import finish, markdown_table, say

import package
from dask_cluster import dask_cluster


def timed_batch(folder, out, **how):
    start = time.perf_counter()
    records = package.seamless_ao.batch([str(folder)], output_dir=str(out), force=True, progress=lambda line: None,
                                        **how, **SETTINGS)
    seconds = time.perf_counter() - start
    failed = [r for r in records if r.status != "baked"]
    assert not failed, failed
    return seconds


def median_batch(folder, out, runs, **how):
    timed_batch(folder, out, **how)                        # warm-up: the workers' first Blender start
    return statistics.median(timed_batch(folder, out, **how) for _ in range(runs))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--assets", type=int, default=8)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2, 4])
    args = parser.parse_args(package.script_arguments())
    # the workers bake with this Python (the bpy module), whatever blender a PATH may hold
    environment = {package.seamless_ao.operators.batch.asset_process.BLENDER_VARIABLE: sys.executable}
    rows, first = [], None
    with tempfile.TemporaryDirectory() as scratch:
        scratch = pathlib.Path(scratch)
        folder, out = scratch / "assets", scratch / "out"
        folder.mkdir()
        make_assets(folder, args.assets)
        for workers in args.workers:
            with dask_cluster(scratch / "dask{}".format(workers), workers=workers,
                              environment=environment) as (address, _):
                seconds = median_batch(folder, out, args.runs, scheduler=address)
            first = first or seconds
            rows.append(("Dask, {} worker{}".format(workers, "s" if workers > 1 else ""), "{:.1f}".format(seconds),
                         "{:.2f}".format(seconds / args.assets), "{:.2f}".format(first / seconds)))
        seconds = median_batch(folder, out, args.runs, jobs=2)
        rows.append(("local, --jobs 2", "{:.1f}".format(seconds), "{:.2f}".format(seconds / args.assets),
                     "{:.2f}".format(first / seconds)))
    say("{} GLB assets (subdivided Suzanne on a floor, {} rays, {}² bake, {}² occlusion texture), median of {} runs "
        "on this machine's 2 CPU cores, which every worker shares".format(
            args.assets, SETTINGS["rays"], SETTINGS["image_size"], SETTINGS["texture_size"], args.runs))
    say()
    say(markdown_table(["batch", "wall s", "s per asset", "speed-up over 1 worker"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
