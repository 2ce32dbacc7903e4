"""Benchmark: The proxy's cubes at each Quality: accuracy and time of the bake (issue 56).

    .venv/5.0/bin/python tests/bench/bench_proxy_cells.py [--meshes million_suzanne million_scan dense]
        [--qualities GOOD FINAL] [--runs 3] [--work-dir out/bench]

A mesh far finer than its image has its charts made on a texel-scale proxy
(core/charts/coarse.py): its vertices clustered in cubes PROXY_CELL_TEXELS
wide, or FINE_PROXY_CELL_TEXELS from FINE_PROXY_FROM_RAYS rays per texel
where the mesh has as many triangles per such cube (proxy_cell_texels).
Each mesh is baked through the operator at each Quality preset three ways:
its layout on a proxy of either cube size, and on the whole mesh (no proxy),
whatever the rule would take; the row the rule takes is marked. Seconds are
the operator's, warm, median of --runs runs; the error is report.py's: what
the node group shows at 2000 visible points against its plain 4096-ray
reference (cached in --work-dir/cache, shared with report.py and
bench_million.py).
"""

import argparse

import bpy

from common import finish, markdown_table, say

import bench_million
import report
from accuracy import errors, shown_seamless
from seamless_ao.core import layout
from seamless_ao.core.charts import coarse
from seamless_ao.core.settings import PRESETS, BakeSettings
from seamless_ao.operators.adapters.mesh_data import read_triangles

#: The layouts each preset is baked with: (label, proxy cube side in texels, or None for the whole mesh).
LAYOUTS = [("proxy, {:g}-texel cubes".format(coarse.PROXY_CELL_TEXELS), coarse.PROXY_CELL_TEXELS),
           ("proxy, {:g}-texel cubes".format(coarse.FINE_PROXY_CELL_TEXELS), coarse.FINE_PROXY_CELL_TEXELS),
           ("the whole mesh", None)]


def forced_layout(cell):
    """Make every bake lay out on a proxy of ``cell``-texel cubes (None: on the whole mesh) until undone; returns
    the undo."""
    original = layout.proxy_cell_texels
    layout.proxy_cell_texels = lambda *args, **kwargs: cell

    def undo():
        layout.proxy_cell_texels = original
    return undo


def rule_takes(mesh, quality):
    """The label of the layout the bake's own rule takes for ``quality`` on a TriangleMesh."""
    size, rays = PRESETS[quality]
    cell = coarse.proxy_cell_texels(mesh, BakeSettings().compare_angle, rays, image_size=size)
    return next(label for label, layout_cell in LAYOUTS if layout_cell == cell)


def main():
    report.MESHES.update(bench_million.MILLION_MESHES)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=["million_suzanne", "million_scan", "dense"],
                        choices=list(report.MESHES))
    parser.add_argument("--qualities", nargs="+", default=["GOOD", "FINAL"], choices=list(PRESETS))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--work-dir", default="out/bench", help="the reference cache (shared with report.py)")
    args = parser.parse_args()
    rows = []
    for name in args.meshes:
        ob, loops, (triangle, bary, normals), reference = report.fresh_with_reference(name, args.work_dir)
        mesh = read_triangles(ob.data)[0]
        report.seamless_bake(ob, quality="DRAFT")                        # warm
        for quality in args.qualities:
            taken = rule_takes(mesh, quality)
            for label, cell in LAYOUTS:
                undo = forced_layout(cell)
                try:
                    seconds, image, stages = report.seamless_median_bake(ob, args.runs, quality=quality)
                finally:
                    undo()
                rmse = errors(shown_seamless(ob, bpy.data.images[image], loops, triangle, bary, normals),
                              reference)[0]
                rows.append([name, "{} ({}², {} rays)".format(quality.title(), *PRESETS[quality]),
                             label + (" (the rule's)" if label == taken else ""), "{:.2f}".format(seconds),
                             "{:.2f}".format(stages.get("charts", 0.0) + stages.get("injectivity", 0.0)),
                             "{:.4f}".format(rmse)])
                print(" | ".join(rows[-1]), flush=True)
    say("Median of {} bakes through the operator; charts s is the charts and injectivity stages together.".format(
        args.runs))
    say()
    say(markdown_table(["mesh", "quality", "laid out on", "seconds", "charts s", "RMSE"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
