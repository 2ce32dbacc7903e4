"""Benchmark: The Raycast node's BVH from one batch to the next, by Blender version.

Does Blender's Geometry Nodes Raycast node keep its target's BVH from one evaluation to the next, and what does
casting small batches one ray at a time save where it does not.

    .venv/5.0/bin/python tests/bench/bench_raycast_evaluations.py [--runs 3] [--blenders 4.2 5.0 5.2 PYTHON ...]

Each Blender given runs the measurements in a process of its own: a version's ``.venv/<version>`` (``make setup
BLENDER=<version>``), or the Python of another virtualenv holding a ``bpy`` wheel (and xatlas), given by its
path.  The meshes: Suzanne subdivided four and five times (a quarter of a million and a million triangles),
smooth shaded.  Measured:

* the Geometry Nodes caster (operators/adapters/casters.py) casting a batch of 1,000 rays through the node, then
  another: where the second costs as much as the first, the node built its BVH again;
* the cheapest bake, 256², 1 ray, Geometry Nodes, through the operator, warm, the median of ``--runs``: as the
  caster casts now, and, where the node builds its BVH at every batch, as it cast before (every batch through
  the node, a one-ray batch first to build the BVH: ``casters.RAYCAST_KEEPS_BVH`` set).
"""

import argparse
import pathlib
import time

import numpy as np

from common import ROOT, child_result, finish, markdown_table, print_result, say

import report

#: The meshes, by label: report.py's (its "dense") and bench_million.py's Suzanne.
MESHES = {"250k": "dense", "1M": "million_suzanne"}


def one_blender(runs):
    """The measurements in this Blender: ``{"version", "keeps", "rows": [[mesh, triangles, first ms, second ms,
    bake s now, bake s every batch through the node or None]]}``."""
    import bpy

    from seamless_ao.operators.adapters import casters
    from seamless_ao.operators.adapters.mesh_data import read_triangles

    report.MESHES.setdefault("million_suzanne", lambda: report.suzanne(5, name="Million Suzanne"))
    rows = []
    for label, name in MESHES.items():
        ob = report.fresh(name)
        mesh, _ = read_triangles(ob.data)
        rng = np.random.default_rng(0)
        directions = rng.normal(size=(1000, 3))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
        origins = rng.uniform(-1.0, 1.0, (1000, 3))
        caster = casters.NodesCaster(mesh.positions, mesh.triangles)
        try:
            batches = []
            for _ in range(2):
                start = time.perf_counter()
                caster._evaluate(origins, directions, 1.0)
                batches.append(1e3 * (time.perf_counter() - start))
        finally:
            caster.free()
        cheapest = dict(image_size=256, rays=1, ray_caster="GEOMETRY_NODES")
        report.seamless_bake(ob, **cheapest)                                   # warm
        now = report.seamless_median_bake(ob, runs, **cheapest)[0]
        before = None
        if not casters.RAYCAST_KEEPS_BVH:
            casters.RAYCAST_KEEPS_BVH = True
            try:
                before = report.seamless_median_bake(ob, runs, **cheapest)[0]
            finally:
                casters.RAYCAST_KEEPS_BVH = False
        rows.append([label, len(mesh.triangles), batches[0], batches[1], now, before])
        print(rows[-1], flush=True)
    return {"version": bpy.app.version_string, "keeps": casters.RAYCAST_KEEPS_BVH, "rows": rows}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--blenders", nargs="+", default=["4.2", "5.0", "5.2"])
    parser.add_argument("--one", action="store_true", help="measure in this Blender and hand the result back")
    args = parser.parse_args()
    if args.one:
        print_result(one_blender(args.runs))
        return
    results = []
    for version in args.blenders:
        # a version set up by make, or the Python of any other virtualenv holding a bpy wheel (and xatlas)
        python = pathlib.Path(version) if "/" in version else ROOT / ".venv" / version / "bin" / "python"
        if not python.exists():
            say("Blender {}: not set up here (make setup BLENDER={}), left out.".format(version, version))
            continue
        results.append(child_result(__file__, "--one", "--runs", str(args.runs), python=python))
    say("Suzanne subdivided four and five times; a batch of 1,000 rays through the node, twice; the cheapest bake "
        "(256², 1 ray, Geometry Nodes) through the operator, median of {} warm runs.".format(args.runs))
    say()
    rows = []
    for result in results:
        for mesh, triangles, first, second, now, before in result["rows"]:
            rows.append([result["version"], "yes" if result["keeps"] else "no", mesh, "{:,}".format(triangles),
                         "{:.1f}".format(first), "{:.1f}".format(second), "{:.2f}".format(now),
                         "-" if before is None else "{:.2f}".format(before),
                         "-" if before is None else "{:.2f}".format(now / before)])
    say(markdown_table(["Blender", "node keeps its BVH", "mesh", "triangles", "first batch ms", "second batch ms",
                        "cheapest bake s", "every batch through the node s", "ratio"], rows))
    say()
    say("Where the node keeps its BVH, the second batch costs a fraction of the first, and the caster casts every "
        "batch through the node as before; where it does not, batches under a tenth of a ray per triangle (on 2 "
        "cores) are cast one ray at a time on one mathutils BVH (casters.SINGLE_RAYS_PER_TRIANGLE).")


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)           # a --one run says nothing: it writes no page
