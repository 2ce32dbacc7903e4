"""Take the AO out of Blender: one texture on the user's own UV map, or per-corner colours.

Both evaluate exactly what the ``Seamless AO`` node group shows (see
:mod:`..image.shown`), from the baked image and the AO_X/Y/Z UVs; no ray is cast.
"""

import numpy as np

from ..arrays.geometry2d import closest_barycentric, cross2d
from ..atlas.raster import rasterise_triangles
from ..image.fill import pull_push
from ..image.shown import blended_ao
from .packings import BY_ID, pack_channels
from .png import encode_png


def shown_at(ao_image, layer_uv, corner_normals, triangle, bary, strength=1.0, interreflection=0.0):
    """The blend at surface points.

    Parameters
    ----------
    ao_image : (h, w) float
    layer_uv : (t, 3 layers, 3 corners, 2) float
    corner_normals : (t, 3, 3) float, object space
    triangle : (k,) int
    bary : (k, 3) float
    strength, interreflection : float, or (t,) float per triangle
        The node's inputs (its material's), see :func:`..image.shown.blended_ao`.

    Returns
    -------
    (k,) float64
    """
    uv = np.einsum("kc,klcd->kld", bary, layer_uv[triangle])
    normals = np.einsum("kc,kcd->kd", bary, corner_normals[triangle])
    per_point = [value if np.isscalar(value) else np.asarray(value)[triangle] for value in (strength, interreflection)]
    return blended_ao(ao_image, uv, normals, *per_point)


def resample_to_uv(ao_image, layer_uv, corner_normals, target_uv, size, padding, degenerate=None,
                   strength=1.0, interreflection=0.0, per_triangle=None):
    """The blended AO laid out on another UV map (e.g. the user's unwrap).

    Parameters
    ----------
    ao_image : (h, w) float, the baked atlas
    layer_uv : (t, 3, 3, 2) AO_X/Y/Z UVs of every triangle corner
    corner_normals : (t, 3, 3) object-space shading normals at the corners
    target_uv : (t, 3, 2) the target UV map at every triangle corner
    size : int or (width, height)
    padding : int
        Texels around every island that get the island's edge values
        (bilinear filtering and mip-mapping at island borders do not bleed);
        the rest of the image is filled smoothly from them.
    degenerate : (t,) bool, optional, triangles to skip
    strength, interreflection : float or (t,) float, the node's inputs (see :func:`shown_at`)
    per_triangle : (t, c) float, optional, values of each triangle laid out on the same texels (the
        material's roughness and metallic, for a packed image)

    Returns
    -------
    image : (height, width) float32
    coverage : (height, width) int8, 0 covered, 1 near, 2 padding, 3 filled
    channels : (height, width, c) float32, ``per_triangle`` laid out (only when it is given)
    """
    width, height = (size, size) if np.isscalar(size) else size
    target = np.asarray(target_uv, dtype=np.float64) * [width, height]
    area = np.abs(cross2d(target[:, 1] - target[:, 0], target[:, 2] - target[:, 0]))
    live = np.flatnonzero((area > 0) & (True if degenerate is None else ~degenerate))
    texels = rasterise_triangles(target, live, width, height, padding)
    x = (texels.index % width).astype(np.float64) + 0.5
    y = (texels.index // width).astype(np.float64) + 0.5
    bary = np.stack(closest_barycentric(target[texels.member], x, y), axis=1)
    values = shown_at(ao_image, layer_uv, corner_normals, texels.member, bary, strength, interreflection)
    image = np.zeros(width * height)
    weight = np.zeros(width * height)
    image[texels.index] = values
    weight[texels.index] = 1.0
    coverage = np.full(width * height, 3, dtype=np.int8)
    coverage[texels.index] = texels.kind
    filled = pull_push(image.reshape(height, width), weight.reshape(height, width))
    if per_triangle is None:
        return filled.astype(np.float32), coverage.reshape(height, width)
    per_triangle = np.asarray(per_triangle, dtype=np.float64).reshape(len(target), -1)
    channels = np.empty((height, width, per_triangle.shape[1]), dtype=np.float32)
    for c in range(per_triangle.shape[1]):
        laid = np.zeros(width * height)
        laid[texels.index] = per_triangle[texels.member, c]
        channels[:, :, c] = pull_push(laid.reshape(height, width), weight.reshape(height, width))
    return filled.astype(np.float32), coverage.reshape(height, width), channels


def texel_uv(width, height):
    """(height, width, 2) float64: the UV of each texel's centre, rows bottom up (Blender's pixel order)."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    return np.stack(np.broadcast_arrays(u[None, :], v[:, None]), axis=-1)


def sample_repeat(values, uv):
    """Bilinear lookup of ``values`` (h, w), rows bottom up, at ``uv`` (..., 2), texel centres at half-integer
    texels, repeating outside [0, 1] as an Image Texture node does by default: (...) float64."""
    height, width = values.shape
    x = np.asarray(uv[..., 0], dtype=np.float64) * width - 0.5
    y = np.asarray(uv[..., 1], dtype=np.float64) * height - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = x - x0, y - y0
    x0, y0 = x0.astype(np.int64) % width, y0.astype(np.int64) % height
    x1, y1 = (x0 + 1) % width, (y0 + 1) % height
    return ((1 - fx) * (1 - fy) * values[y0, x0] + fx * (1 - fy) * values[y0, x1]
            + (1 - fx) * fy * values[y1, x0] + fx * fy * values[y1, x1])


def packed_values(channels, textures):
    """(roughness, metallic), each (h, w): per-triangle values laid into the image (``channels`` (h, w,
    2 + k): roughness, metallic, then one column per texture, 1 where its triangles lie, as
    :func:`resample_to_uv` lays them), with each texture's own texels where its triangles lie.

    Parameters
    ----------
    channels : (h, w, 2 + k) float
    textures : list of k ``(value, texels)``: ``value`` 0 roughness or 1 metallic, ``texels`` (h', w') float,
        read repeating through the image's own texel centres
    """
    height, width = channels.shape[:2]
    laid = [channels[:, :, 0].copy(), channels[:, :, 1].copy()]
    uv = texel_uv(width, height)
    for j, (v, texture) in enumerate(textures):
        where = channels[:, :, 2 + j] > 0.5
        laid[v][where] = sample_repeat(texture, uv[where])
    return laid


def resampled_png(laid, packing, bit_depth, textures=()):
    """The PNG bytes of a resample: :func:`resample_to_uv`'s result ``laid`` (with its channels where the
    packing carries the material, :func:`packed_values`' ``textures`` read into them) packed as ``packing``
    (:mod:`.packings`), ``bit_depth`` (8 or 16) bits per channel, rows top first as PNG stores them."""
    material = packed_values(laid[2], textures) if len(laid) > 2 else (None, None)
    rgba = pack_channels(laid[0], packing, *material)
    return encode_png(rgba[::-1, :, :BY_ID[packing].png_channels], int(bit_depth))


def corner_values(ao_image, layer_uv, corner_normals, strength=1.0, interreflection=0.0):
    """The blend at every triangle corner: (t, 3) float64 (node inputs as in :func:`shown_at`)."""
    count = len(layer_uv)
    triangle = np.repeat(np.arange(count), 3)
    bary = np.tile(np.eye(3), (count, 1))
    return shown_at(ao_image, layer_uv, corner_normals, triangle, bary, strength, interreflection).reshape(count, 3)


def vertex_average(corner_values, corner_vertex, vertex_count):
    """Per-vertex mean of per-corner values; 1 (open) for a vertex no corner uses.

    Parameters
    ----------
    corner_values : (c,) float, one per face corner (loop)
    corner_vertex : (c,) int, the vertex of each corner
    vertex_count : int

    Returns
    -------
    (vertex_count,) float64
    """
    total = np.bincount(corner_vertex, weights=corner_values, minlength=vertex_count)
    count = np.bincount(corner_vertex, minlength=vertex_count)
    return np.where(count > 0, total / np.maximum(count, 1), 1.0)
