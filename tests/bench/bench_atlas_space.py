"""Benchmark: Where the image goes, on the scan and the interior.

    .venv/5.0/bin/python tests/bench/bench_atlas_space.py [--sizes 256 1024]

Issue 30 asks for atlas use of at least 40% at 256² and 50% at 1024², and to
measure first what takes the space. The meshes are bench_fixed_cost's scan
and interior, read as the bake operator reads them, laid out at the bake's
default settings. Every texel of the image is counted once: covered (its
centre lies in a chart triangle), near (bilinear filtering at a chart's rim
reads it), a padding ring around a chart, or empty. Covered, near and padding
texels are also counted by the kind of chart they belong to (core/atlas/packing.py:
a point chart is one texel, a small chart at most SMALL_TEXELS across its
narrow side is shelf-packed with its ring, a large one goes to xatlas with
padding). Atlas use is the report's own figure: the charts' area over the
image's, so covered texels come close to it. The gap is the fewest texels
left free between the covered and near texels of two large charts.
"""

import argparse

import numpy as np

from common import finish, markdown_table, say

from bench_fixed_cost import scene
from layout_checks import chart_kinds, least_gap
from seamless_ao.core.atlas import raster
from seamless_ao.core.layout import build_layout
from seamless_ao.core.settings import BakeSettings
from seamless_ao.operators.adapters.mesh_data import read_triangles

KINDS = ("point", "small", "large")


def space(layout):
    """Counts of the image's texels: by texel kind, and by chart kind; and the charts of each kind."""
    atlas, texels = layout.atlas, layout.texels
    image = atlas.width * atlas.height
    texel_kind = {name: int(np.count_nonzero(texels.kind == value))
                  for name, value in (("covered", raster.COVERED), ("near", raster.NEAR),
                                      ("padding", raster.PADDING))}
    texel_kind["empty"] = image - len(texels)
    kind = chart_kinds(atlas)
    of_texel = kind[atlas.member_chart[texels.member]]
    return dict(image=image, texels=texel_kind,
                by_chart=[int(np.count_nonzero(of_texel == k)) for k in range(3)],
                charts=[int(np.count_nonzero(kind == k)) for k in range(3)],
                use=atlas.utilisation, padding=atlas.padding, density=atlas.density, gap=least_gap(layout, kind))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 1024])
    args = parser.parse_args()
    settings = BakeSettings()
    rows, kind_rows = [], []
    for name in ("scan", "interior"):
        ob = scene(name)
        mesh, _ = read_triangles(ob.data)
        for size in args.sizes:
            layout = build_layout(mesh, settings.compare_angle, image_size=size, padding=settings.padding)
            found = space(layout)
            share = {k: v / found["image"] for k, v in found["texels"].items()}
            rows.append([name, "{}²".format(size), " / ".join("{:,}".format(n) for n in found["charts"]),
                         "{:.0%}".format(found["use"]), "{:.0%}".format(share["covered"]),
                         "{:.0%}".format(share["near"]), "{:.0%}".format(share["padding"]),
                         "{:.0%}".format(share["empty"]), str(found["padding"]), str(found["gap"])])
            kind_rows.append([name, "{}²".format(size)] + ["{:.0%}".format(n / found["image"])
                                                          for n in found["by_chart"]])
            print(rows[-1], kind_rows[-1], flush=True)
    say("Share of the image's texels, at the bake's default settings (padding {} texels at most).".format(
        settings.padding))
    say()
    say(markdown_table(["mesh", "image", "charts point / small / large", "atlas use", "covered", "near",
                        "padding rings", "empty", "xatlas padding", "gap"], rows))
    say()
    say("Covered, near and padding texels together, by the kind of chart they belong to (share of the image).")
    say()
    say(markdown_table(["mesh", "image"] + ["{} charts".format(k) for k in KINDS], kind_rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
