"""Issue 13: the generated real assets bake as accurately as the hard cases."""

import numpy as np
import pytest

from accuracy import P99_LIMIT, RMSE_LIMIT
import real_assets
from marks import heavy
from package import seamless_ao


#: (asset, shaded smooth, image sizes it must reach the limits at).  Each asset as generated (flat
#: shaded), and the noisy scan also shaded smooth, as scans are shown.  Flat shaded, the scan's
#: faces tilt up to about 17 degrees from their neighbours (scanner noise on the slivers near its
#: poles), finer than a 512² texel: no texture at 512² holds that (Cycles' own 512² bake is further
#: off, see tests/bench/bench_assets.py and README "Generated real assets"), so flat it is held to
#: the limits from 1024² on.
#: 512² is held where the image resolves the asset: not the hall (a 512² texel, 38 cm, is wider than its 20 cm floor
#: slab and its wall overhang; bench_assets.py measures us 0.047 and Cycles 0.093 there) nor the flat noisy scan.
ACCURACY_CASES = [(name, False, (1024,) if name in ("interior", "noisy_scan") else (512, 1024))
                  for name in sorted(real_assets.ASSETS)] + [("noisy_scan", True, (512, 1024))]


@heavy
@pytest.mark.parametrize("name, smooth, sizes", ACCURACY_CASES,
                         ids=["{}{}".format(c[0], "-smooth" if c[1] else "") for c in ACCURACY_CASES])
def test_asset_bakes_as_accurately_as_the_hard_cases(name, smooth, sizes, addon, fresh_scene):
    """A real bake at 256² (finite, in [0, 1]); then RMSE <= 0.03 and 99th percentile <= 0.12 of what
    the node group shows, against the plain 4096-ray reference (tests/support/plain_reference.py) at 1000 visible
    points, at each of ``sizes``.  (At 500, the p99 was the fifth-worst point: on the flat noisy scan, whose
    worst points sit on sliver facets tilted 30-120 degrees from their neighbours, four other seeds of 500
    points gave 0.065-0.112 where seed 3 gave 0.103 to one layout and 0.124 to another as accurate.)"""
    import bpy
    from blender_checks import image_array
    from blender_scenes import add_object, mesh_from_arrays
    from accuracy import errors, shown_seamless
    from plain_reference import reference_at_visible_points
    from seamless_ao.operators.adapters.mesh_data import read_triangles

    positions, triangles = real_assets.ASSETS[name]()
    ob = add_object(name, mesh_from_arrays(name, positions, triangles, smooth=smooth))
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals, reference, max_distance = reference_at_visible_points(mesh, count=1000)
    report = seamless_ao.bake([ob], image_size=256, rays=8, auto_distance=False, max_distance=max_distance)
    values = image_array(bpy.data.images[report.image])                  # 256²: bakes, nothing more asked
    assert report.width == 256 and np.isfinite(values).all() and 0.0 <= values.min() <= values.max() <= 1.0
    for size in sizes:
        report = seamless_ao.bake([ob], image_size=size, rays=32, auto_distance=False, max_distance=max_distance)
        shown = shown_seamless(ob, bpy.data.images[report.image], loops, triangle, bary, normals)
        rmse, p99 = errors(shown, reference)
        print("{} {}²: RMSE {:.4f}, p99 {:.4f}, {:.1f} s".format(name, size, rmse, p99, report.seconds))
        assert rmse <= RMSE_LIMIT and p99 <= P99_LIMIT, (name, size, rmse, p99)
