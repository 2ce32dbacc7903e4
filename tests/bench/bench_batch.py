"""Benchmark: a folder of assets, one worker against two.

    .venv/5.0/bin/python tests/bench/bench_batch.py [--assets 8] [--runs 3] [--jobs 1 2]

Writes ``--assets`` GLB files (subdivided Suzanne on a floor slab, about 16k
triangles each, with a UV map), then bakes the folder at 512², 32 rays with
``--force`` for each ``--jobs`` value.  Each row: median wall seconds of
``--runs`` batches (the first batch of the script is an untimed warm-up),
seconds per asset, and the speed-up over the first row.  Every run starts
fresh worker processes, so the cost of starting Blender in each is included.
Last, the first record of the last run's ``--report`` file, as written.
"""

import argparse
import json
import pathlib
import statistics
import tempfile
import time

from common import finish, markdown_table, say

import addon_utils
import bpy

import package
from blender_scenes import suzanne

SETTINGS = dict(rays=32, image_size=512, texture_size=512)


def make_assets(folder, count):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    suzanne(subdivisions=2)
    bpy.ops.mesh.primitive_plane_add(size=4.0, location=(0.0, 0.0, -1.0))
    addon_utils.enable("io_scene_gltf2", default_set=False)
    paths = []
    for k in range(count):
        path = folder / "asset_{:03d}.glb".format(k)
        bpy.ops.export_scene.gltf(filepath=str(path), export_format="GLB")
        paths.append(path)
    return paths


def timed_batch(folder, out, jobs):
    start = time.perf_counter()
    records = package.seamless_ao.batch([str(folder)], output_dir=str(out), jobs=jobs, force=True,
                                        progress=lambda line: None, report=str(out / "report.json"), **SETTINGS)
    seconds = time.perf_counter() - start
    failed = [r for r in records if r.status != "baked"]
    assert not failed, failed
    return seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--assets", type=int, default=8)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args(package.script_arguments())
    with tempfile.TemporaryDirectory() as scratch:
        folder, out = pathlib.Path(scratch) / "assets", pathlib.Path(scratch) / "out"
        folder.mkdir()
        make_assets(folder, args.assets)
        timed_batch(folder, out, args.jobs[0])                  # warm-up: disk cache, first worker start
        rows, first = [], None
        for jobs in args.jobs:
            seconds = statistics.median(timed_batch(folder, out, jobs) for _ in range(args.runs))
            first = first or seconds
            rows.append((jobs, "{:.1f}".format(seconds), "{:.2f}".format(seconds / args.assets),
                         "{:.2f}".format(first / seconds)))
        report = json.loads((out / "report.json").read_text())
    say("{} GLB assets (subdivided Suzanne on a floor, {} rays, {}² bake, {}² occlusion texture), "
          "median of {} runs".format(args.assets, SETTINGS["rays"], SETTINGS["image_size"],
                                    SETTINGS["texture_size"], args.runs))
    say(markdown_table(["jobs", "wall s", "s per asset", "speed-up"], rows))
    say()
    say("One record of the last run's `--report` file:")
    say()
    say("```json\n" + json.dumps(report["assets"][0], indent=1) + "\n```")


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
