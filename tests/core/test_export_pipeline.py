"""Issue 53: the export on arrays (core/export/export_pipeline.py), the twin of the bake's pipeline: a bake read
as it renders in, PNG bytes or colours out, every refusal and every material's value decided without Blender."""

import numpy as np
import pytest

from seamless_ao.core.errors import SeamlessAOError
from seamless_ao.core.export.export_pipeline import (BakedSurface, SlotMaterials, color_values, export_packing,
                                                     resampled_image)
from seamless_ao.core.export.packings import BY_ID
from seamless_ao.core.settings import ExportSettings

from png_levels import decode_png

#: The AO the flat image holds everywhere.
AO = 0.25


def square(slot_blend=((1.0, 0.0),)):
    """A unit square of two triangles facing +Z (left: slot 0, right: the last slot), its AO image flat at
    :data:`AO`, every AO layer's UV its own position; and the target UV map, the same square."""
    corners = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0], [0, 1, 0]]], dtype=np.float64)
    target_uv = corners[:, :, :2].copy()
    surface = BakedSurface(
        ao_image=np.full((16, 16), AO), layer_uv=np.repeat(target_uv[:, None], 3, axis=1),
        corner_normals=np.tile([0.0, 0.0, 1.0], (2, 3, 1)), triangle_area=np.full(2, 0.5),
        degenerate=np.zeros(2, dtype=bool), triangle_slot=np.array([0, len(slot_blend) - 1]),
        slot_blend=np.array(slot_blend, dtype=np.float64))
    return surface, target_uv


def levels(png):
    values, bit_depth = decode_png(png)
    return values.astype(np.float64) / (2 ** bit_depth - 1)


def test_the_resampled_png_shows_what_the_node_shows_with_each_slots_strength():
    surface, target_uv = square(slot_blend=((1.0, 0.0), (0.0, 0.0)))    # right: Strength 0, no AO at all
    settings = ExportSettings.from_kwargs(size=32, packing="GREY", padding=2)
    grey = levels(resampled_image(surface, target_uv, settings, "Square", "UVMap"))[::-1, :, 0]   # rows bottom up
    x, y = np.meshgrid(np.arange(32) + 0.5, np.arange(32) + 0.5)
    left, right = (x + y < 30), (x + y > 34)                             # clear of the diagonal both share
    assert np.allclose(grey[left], AO, atol=1e-4) and np.allclose(grey[right], 1.0, atol=1e-4)
    plain = ExportSettings.from_kwargs(size=32, packing="GREY", padding=2, material_strength=False)
    assert np.allclose(levels(resampled_image(surface, target_uv, plain, "Square", "UVMap")), AO, atol=1e-4)


def test_a_uv_map_that_cannot_hold_the_ao_is_refused_by_name_unless_asked():
    surface, target_uv = square()
    stacked = np.repeat(target_uv[:1], 2, axis=0)                       # both triangles on the same UVs
    settings = ExportSettings.from_kwargs(size=16)
    with pytest.raises(SeamlessAOError, match="'Square': its UV map 'Stacked' cannot hold the AO: .*shares UV space"):
        resampled_image(surface, stacked, settings, "Square", "Stacked")
    png = resampled_image(surface, stacked, settings.replace(unfit_uv_map=True), "Square", "Stacked")
    assert decode_png(png)[0].shape == (16, 16, 3)


def test_a_packing_that_carries_the_material_reads_each_slot_and_its_texture():
    """ORM: R the AO, G each slot's roughness (the right slot's from a texture read through the same UV map),
    B each slot's metallic."""
    surface, target_uv = square(slot_blend=((1.0, 0.0), (1.0, 0.0)))
    texture = np.tile(np.linspace(0.0, 1.0, 8), (8, 1))                  # roughness growing with u
    materials = SlotMaterials(values=np.array([[0.2, 0.0], [0.9, 0.75]]), texture_use=np.array([[False], [True]]),
                              textures=[(0, texture)])
    settings = ExportSettings.from_kwargs(size=32, packing="ORM", padding=2, gltf_occlusion=False)
    with pytest.raises(ValueError, match="ORM packing carries the material"):
        resampled_image(surface, target_uv, settings, "Square", "UVMap")
    rgb = levels(resampled_image(surface, target_uv, settings, "Square", "UVMap", materials))[::-1]
    x, y = np.meshgrid(np.arange(32) + 0.5, np.arange(32) + 0.5)
    left, right = (x + y < 30), (x + y > 34)
    assert np.allclose(rgb[:, :, 0][left | right], AO, atol=1e-4)
    assert np.allclose(rgb[:, :, 1][left], 0.2, atol=1e-4) and np.allclose(rgb[:, :, 2][left], 0.0, atol=1e-4)
    assert np.allclose(rgb[:, :, 2][right], 0.75, atol=1e-4)
    at = x[right] / 32 * 8 - 0.5                                        # texel coordinate of each texel's u
    low = np.floor(at)
    ramp = np.linspace(0.0, 1.0, 8)                                      # read bilinearly, repeating past u = 1
    expected = (1 - (at - low)) * ramp[low.astype(int) % 8] + (at - low) * ramp[(low.astype(int) + 1) % 8]
    assert np.allclose(rgb[:, :, 1][right], expected, atol=0.02)
    assert np.ptp(rgb[:, :, 1][right]) > 0.5                             # the texture, not the slot's own 0.9


def test_a_packing_the_gltf_occlusion_cannot_read_is_refused_with_its_sentence():
    assert export_packing(ExportSettings.from_kwargs(packing="ORM")) is BY_ID["ORM"]
    with pytest.raises(SeamlessAOError, match="Unity Mask Map packing carries the AO in G.*turn glTF occlusion off"):
        export_packing(ExportSettings.from_kwargs(packing="UNITY_MASK", gltf_occlusion=True))


def test_colour_values_on_corners_and_on_points():
    """Corners get the node's value, loops no triangle reaches stay open (1); a point is the mean of its
    corners."""
    surface, _ = square(slot_blend=((1.0, 0.0), (0.5, 0.0)))           # right: half strength
    loops = np.array([[0, 1, 2], [3, 4, 5]])
    corners = color_values(surface, ExportSettings.from_kwargs(domain="CORNER"), loops, 7)
    half = 1.0 - 0.5 * (1.0 - AO)
    assert np.allclose(corners, [AO] * 3 + [half] * 3 + [1.0])
    loop_vertex = np.array([0, 1, 2, 1, 3, 2, 4])
    points = color_values(surface, ExportSettings.from_kwargs(domain="POINT"), loops, 7, loop_vertex, 5)
    assert np.allclose(points, [AO, (AO + half) / 2, (AO + half) / 2, half, 1.0])
