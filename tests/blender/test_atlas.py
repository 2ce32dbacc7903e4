"""The atlas of a mesh read from Blender (Suzanne): lookups, layers, finite texels."""

import numpy as np
import pytest

from blender_scenes import suzanne
from layout_checks import check_layers_do_not_overlap, check_lookups, check_texels_finite
from seamless_ao.core.layout import build_layout


@pytest.fixture(scope="module")
def suzanne_layout():
    import bpy
    from seamless_ao.operators.adapters.mesh_data import read_triangles
    bpy.ops.wm.read_factory_settings(use_empty=True)
    mesh, _ = read_triangles(suzanne(2).data)
    return build_layout(mesh, image_size=512)


def test_suzanne_lookups_and_layers(suzanne_layout):
    layout = suzanne_layout
    assert layout.atlas.width == layout.atlas.height == 512
    assert 0.3 < layout.atlas.utilisation <= 1.0
    check_lookups(layout, np.random.default_rng(1))
    check_layers_do_not_overlap(layout)
    check_texels_finite(layout)
