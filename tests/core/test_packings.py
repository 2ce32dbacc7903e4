"""Issue 53: a packing is one record (core/export/packings.py); the settings' choices, the channels a resample writes and
the PNG it becomes are read off it, and the export's array half (resample -> PNG bytes) runs without Blender."""

import numpy as np
import pytest

from seamless_ao.core.export.packings import PACKINGS, pack_channels
from seamless_ao.core.settings import GLTF_PACKING_ITEMS, PACKING_ITEMS, ExportSettings, GltfSettings
from seamless_ao.core.errors import SeamlessAOError
from seamless_ao.core.export.transfer import resample_to_uv, resampled_png

from png_levels import decode_png


@pytest.mark.parametrize("packing", PACKINGS, ids=lambda packing: packing.id)
def test_each_packing_puts_the_ao_and_the_material_where_its_record_says(packing):
    rng = np.random.default_rng(3)
    ao, roughness, metallic = (rng.random((4, 5)).astype(np.float32) for _ in range(3))
    rgba = pack_channels(ao, packing.id, roughness, metallic)
    expected = {packing.occlusion: ao}
    for channel, values in ((packing.roughness, roughness), (packing.metallic, metallic),
                            (packing.smoothness, 1.0 - roughness)):
        if channel >= 0:
            expected[channel] = values
    for channel in range(4):
        if channel in expected:
            want = expected[channel]
        elif channel in packing.zero:
            want = 0.0
        else:
            want = ao if packing.grey and channel < 3 else 1.0
        assert np.array_equal(rgba[:, :, channel], np.broadcast_to(want, ao.shape).astype(np.float32)), channel


def test_the_settings_choices_are_the_records():
    assert [item[0] for item in PACKING_ITEMS] == [packing.id for packing in PACKINGS]
    assert [item[0] for item in GLTF_PACKING_ITEMS] == [p.id for p in PACKINGS if p.occlusion == 0]
    for packing in PACKINGS:
        ExportSettings.from_kwargs(packing=packing.id)
        if packing.occlusion != 0:
            with pytest.raises(SeamlessAOError, match="carries the AO in {}".format("RGBA"[packing.occlusion])):
                GltfSettings.from_kwargs(texture_packing=packing.id)


@pytest.mark.parametrize("packing", PACKINGS, ids=lambda packing: packing.id)
@pytest.mark.parametrize("bit_depth", [8, 16])
def test_a_resample_becomes_png_bytes_on_arrays_alone(packing, bit_depth):
    """A flat baked atlas (AO 0.25) through one quad's UVs: the PNG holds the packing's channels, the AO
    quantised in its channel over the whole image (pull-push fills the rest with the same value), and the
    material's values (roughness 0.6, metallic 0.2, one per triangle) in theirs."""
    atlas = np.full((8, 8), 0.25)
    layer_uv = np.tile(np.array([[0.1, 0.1], [0.9, 0.1], [0.9, 0.9]]), (2, 3, 1, 1))     # (2, 3 layers, 3, 2)
    normals = np.tile(np.array([0.0, 0.0, 1.0]), (2, 3, 1))
    target = np.array([[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]])
    material = np.array([[0.6, 0.2], [0.6, 0.2]]) if packing.carries_material else None
    laid = resample_to_uv(atlas, layer_uv, normals, target, 16, 2, per_triangle=material)
    levels, depth = decode_png(resampled_png(laid, packing.id, str(bit_depth)))
    top = 2 ** bit_depth - 1
    assert depth == bit_depth and levels.shape == (16, 16, packing.png_channels)
    assert np.all(levels[:, :, packing.occlusion if packing.png_channels > 1 else 0] == round(0.25 * top))
    for channel, value in ((packing.roughness, 0.6), (packing.metallic, 0.2), (packing.smoothness, 0.4)):
        if channel >= 0:
            assert np.all(np.abs(levels[:, :, channel].astype(np.int64) - value * top) <= 1), channel
