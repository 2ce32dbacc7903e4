"""Benchmark: Scene occluders: only what the rays can reach.

    .venv/5.0/bin/python tests/bench/bench_occluders.py [--objects 200] [--runs 3]

Bakes subdivided Suzanne (512², 16 rays, Scene Occluders on, automatic
distance) alone, then with ``--objects`` subdivided spheres (about 8k
triangles each) standing far beyond the maximum ray distance, then once more
with the distance filter switched off (every visible mesh read, as before the
filter).  Each row: median seconds of ``--runs`` bakes after one untimed
warm-up bake, and the occluder triangles the ray caster was given.
"""

import argparse
import statistics
import time

from common import finish, markdown_table, say

import bpy

import package
from blender_scenes import suzanne
from seamless_ao.operators.adapters import mesh_data, session

SETTINGS = dict(image_size=512, rays=16, use_scene_occluders=True)


def far_spheres(count):
    """``count`` subdivided spheres on a ring 100 units out (Suzanne's ray reach is about 1.7)."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=64, radius=1.0)
    source = bpy.context.active_object
    source.location = (100.0, 0.0, 0.0)
    for k in range(1, count):
        copy = source.copy()
        copy.data = source.data.copy()
        copy.location = (100.0 + 3.0 * (k % 20), 3.0 * (k // 20), 0.0)
        bpy.context.scene.collection.objects.link(copy)
    bpy.context.view_layer.update()


def timed(ob, runs):
    """(median seconds, occluder triangles given to the caster)."""
    seen = []
    original = session.scene_occluders                  # as the bake session calls it

    def counting(*args):
        found = original(*args)
        seen.extend(len(triangles) for _, triangles in found)
        return found
    session.scene_occluders = counting
    try:
        package.seamless_ao.bake([ob], **SETTINGS)                     # warm-up
        seen.clear()
        times = []
        for _ in range(runs):
            start = time.perf_counter()
            package.seamless_ao.bake([ob], **SETTINGS)
            times.append(time.perf_counter() - start)
        return statistics.median(times), sum(seen) // runs
    finally:
        session.scene_occluders = original


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=200)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    package.seamless_ao.register()
    ob = suzanne(2)
    rows = []
    seconds, triangles = timed(ob, args.runs)
    rows.append(["Suzanne alone", "on", "{:.2f}".format(seconds), "{:,}".format(triangles)])
    far_spheres(args.objects)
    seconds, triangles = timed(ob, args.runs)
    rows.append(["+ {} far spheres".format(args.objects), "on", "{:.2f}".format(seconds), "{:,}".format(triangles)])
    original = mesh_data.boxes_near
    mesh_data.boxes_near = lambda low, high, lows, highs, reach: original(low, high, lows, highs, float("inf"))
    try:
        seconds, triangles = timed(ob, args.runs)
    finally:
        mesh_data.boxes_near = original
    rows.append(["+ {} far spheres".format(args.objects), "off (every visible mesh)", "{:.2f}".format(seconds),
                 "{:,}".format(triangles)])
    say(markdown_table(["scene", "distance filter", "seconds (median)", "occluder triangles"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
