"""The node group's blend, evaluated in numpy: what a material shows at a surface point.

Used by the tests (the shader must do what this says), the benchmark report
(error is measured on what the user sees) and the exporters.
"""

import numpy as np


def bilinear(image, uv):
    """Sample ``image`` (h, w) at ``uv`` (k, 2) like Blender's Image Texture node
    (Linear interpolation, Extend extension): texel centres at (i + 0.5) / w.

    Returns (k,) float64.
    """
    height, width = image.shape
    x = uv[:, 0] * width - 0.5
    y = uv[:, 1] * height - 0.5
    x0 = np.floor(x)
    y0 = np.floor(y)
    fx, fy = x - x0, y - y0
    x0, y0 = x0.astype(np.int64), y0.astype(np.int64)
    x1, y1 = np.clip(x0 + 1, 0, width - 1), np.clip(y0 + 1, 0, height - 1)
    x0, y0 = np.clip(x0, 0, width - 1), np.clip(y0, 0, height - 1)
    top = image[y1, x0] * (1 - fx) + image[y1, x1] * fx
    bottom = image[y0, x0] * (1 - fx) + image[y0, x1] * fx
    return bottom * (1 - fy) + top * fy


def blend_weights(normals):
    """(k, 3) weights nx², ny², nz² normalised to sum 1 (object-space normals)."""
    squared = np.asarray(normals, dtype=np.float64) ** 2
    return squared / np.maximum(squared.sum(axis=1, keepdims=True), 1e-12)


def blended_ao(image, layer_uv, normals, strength=1.0, interreflection=0.0):
    """What the ``Seamless AO`` group outputs at some surface points.

    Parameters
    ----------
    image : (h, w) float
    layer_uv : (k, 3, 2) UV of each point in layers AO_X, AO_Y, AO_Z
    normals : (k, 3) object-space shading normals

    Returns
    -------
    (k,) float64 in [0, 1]
    """
    weights = blend_weights(normals)
    samples = np.stack([bilinear(image, layer_uv[:, layer]) for layer in range(3)], axis=1)
    ao = (weights * samples).sum(axis=1)
    ao = np.clip(ao / (1.0 - interreflection * (1.0 - ao)), 0.0, 1.0)
    return np.clip(1.0 - strength * (1.0 - ao), 0.0, 1.0)
