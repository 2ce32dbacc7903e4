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


def test_objects_baked_together_keep_their_charts_apart_in_the_uv_maps_they_were_given(fresh_scene, addon):
    """Three objects in one image, read back through the UV maps the bake wrote (not the layout): every
    triangle of one object, in any of AO_X/Y/Z, stays at least two texels from every triangle of another
    (bilinear filtering reads one texel around a point; the padding keeps two), judged by plane_judge."""
    import bpy
    from blender_checks import uv_layer_array
    from plane_judge import boxes_within, triangle_distance
    from seamless_ao.operators.adapters.mesh_data import read_triangles

    head = suzanne(1)
    bpy.ops.mesh.primitive_torus_add(location=(3.0, 0.0, 0.0))
    ring = bpy.context.active_object
    bpy.ops.mesh.primitive_cube_add(location=(0.0, 3.0, 0.0), scale=(2.0, 0.2, 0.5))
    block = bpy.context.active_object
    objects = [head, ring, block]
    report = addon.bake(objects, image_size=256, rays=4)
    size = report.width
    shapes, owner = [], []
    for index, ob in enumerate(objects):
        _, loops = read_triangles(ob.data)
        for name in ("AO_X", "AO_Y", "AO_Z"):
            uv = uv_layer_array(ob.data, name)[loops] * size                     # (t, 3, 2) texel units
            shapes.append(np.unique(uv.reshape(len(uv), -1), axis=0).reshape(-1, 3, 2))
            owner.append(np.full(len(shapes[-1]), index))
    shapes, owner = np.concatenate(shapes), np.concatenate(owner)
    assert np.isfinite(shapes).all() and shapes.min() > 0.0 and shapes.max() < size
    pairs = boxes_within(shapes, np.zeros(len(shapes), dtype=np.int64), 2.0)
    across = pairs[owner[pairs[:, 0]] != owner[pairs[:, 1]]]
    gap = triangle_distance(shapes[across[:, 0]], shapes[across[:, 1]])
    assert len(np.unique(owner)) == 3
    assert (gap >= 2.0 - 1e-6).all(), "objects' charts {:.3g} texels apart".format(gap.min() if len(gap) else 0)
