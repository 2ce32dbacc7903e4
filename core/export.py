"""Take the AO out of Blender: one texture on the user's own UV map, or per-corner colours.

Both evaluate exactly what the ``Seamless AO`` node group shows (see
:mod:`.blend`), from the baked image and the AO_X/Y/Z UVs; no ray is cast.
"""

import numpy as np

from .blend import blended_ao
from .mesh import cross2d
from .raster import closest_barycentric, rasterise_triangles
from .pipeline import pull_push


def shown_at(ao_image, layer_uv, corner_normals, triangle, bary):
    """The blend at surface points.

    Parameters
    ----------
    ao_image : (h, w) float
    layer_uv : (t, 3 layers, 3 corners, 2) float
    corner_normals : (t, 3, 3) float, object space
    triangle : (k,) int
    bary : (k, 3) float

    Returns
    -------
    (k,) float64
    """
    uv = np.einsum("kc,klcd->kld", bary, layer_uv[triangle])
    normals = np.einsum("kc,kcd->kd", bary, corner_normals[triangle])
    return blended_ao(ao_image, uv, normals)


def resample_to_uv(ao_image, layer_uv, corner_normals, target_uv, size, padding=8, degenerate=None):
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

    Returns
    -------
    image : (height, width) float32
    coverage : (height, width) int8, 0 covered, 1 near, 2 padding, 3 filled
    """
    width, height = (size, size) if np.isscalar(size) else size
    target = np.asarray(target_uv, dtype=np.float64) * [width, height]
    area = np.abs(cross2d(target[:, 1] - target[:, 0], target[:, 2] - target[:, 0]))
    live = np.flatnonzero((area > 0) & (True if degenerate is None else ~degenerate))
    texels = rasterise_triangles(target, live, width, height, padding)
    x = (texels.index % width).astype(np.float64) + 0.5
    y = (texels.index // width).astype(np.float64) + 0.5
    bary = np.stack(closest_barycentric(target[texels.member], x, y), axis=1)
    values = shown_at(ao_image, layer_uv, corner_normals, texels.member, bary)
    image = np.zeros(width * height)
    weight = np.zeros(width * height)
    image[texels.index] = values
    weight[texels.index] = 1.0
    coverage = np.full(width * height, 3, dtype=np.int8)
    coverage[texels.index] = texels.kind
    filled = pull_push(image.reshape(height, width), weight.reshape(height, width))
    return filled.astype(np.float32), coverage.reshape(height, width)


def corner_values(ao_image, layer_uv, corner_normals):
    """The blend at every triangle corner: (t, 3) float64."""
    count = len(layer_uv)
    triangle = np.repeat(np.arange(count), 3)
    bary = np.tile(np.eye(3), (count, 1))
    return shown_at(ao_image, layer_uv, corner_normals, triangle, bary).reshape(count, 3)
