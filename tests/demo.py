"""`make demo`: bake the built-in demo scene headless and write its outputs.

    .venv/5.0/bin/python tests/demo.py --output-dir out

Builds the thesis' test scenes (a Cornell box with two blocks, a sphere
hovering over a plane, a subdivided Suzanne) and runs every pipeline step
that exists, printing what it did and what it wrote.
"""

import argparse
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))

import conftest  # noqa: E402  (bpy, and the package as ``seamless_ao``)
import bpy  # noqa: E402

from blender_scenes import demo_scene  # noqa: E402
from seamless_ao.core.adjacency import face_adjacency  # noqa: E402
from seamless_ao.core.clustering import cluster_faces  # noqa: E402
from seamless_ao.operators.mesh_data import read_triangles  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", default="out")
    args = parser.parse_args()
    out = pathlib.Path(args.output_dir).resolve()
    out.mkdir(parents=True, exist_ok=True)
    objects = demo_scene()
    for ob in objects:
        start = time.perf_counter()
        mesh, _ = read_triangles(ob.data)
        topology = face_adjacency(mesh)
        charts = cluster_faces(mesh, topology)
        print("{:<10} {:>7,} triangles -> {:>4} charts ({} split for injectivity) in {:.2f} s".format(
            ob.name, len(mesh.triangles), charts.count, charts.splits, time.perf_counter() - start))
    print("Not done yet: packing, AO rays and the Blender-side bake are not built, so no image was made.")
    blend = out / "demo.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    print("Wrote", blend)


if __name__ == "__main__":
    main()
