"""The AO image from per-texel values: texels without one are filled from their neighbours (pull-push)."""

import numpy as np


def texel_image(texels, values, computed=None):
    """The AO image (height, width) float32 from per-texel values.

    Texels without a computed value (``computed`` False, or not in ``texels``)
    are filled by a pull-push pyramid from the ones that have one, so
    mip-mapping (EEVEE) and any filtering at a distance never pulls in an empty
    (black, i.e. "fully occluded") texel.
    """
    width, height = texels.width, texels.height
    computed = np.ones(len(texels), dtype=bool) if computed is None else computed
    image = np.zeros(width * height, dtype=np.float64)
    weight = np.zeros(width * height, dtype=np.float64)
    image[texels.index[computed]] = values[computed]
    weight[texels.index[computed]] = 1.0
    filled = pull_push(image.reshape(height, width), weight.reshape(height, width))
    return filled.astype(np.float32)


def pull_push(values, weight):
    """Fill where ``weight`` is 0 from a weighted image pyramid; keep the rest exactly."""
    if weight.min() > 0 or weight.max() == 0:
        return np.where(weight > 0, values, values.mean() if weight.max() == 0 else values)
    height, width = values.shape
    sums = values * weight
    # pull: 2x2 box-filter the weighted sums down to 1x1
    levels = [(sums, weight)]
    while levels[-1][0].shape[0] > 1 or levels[-1][0].shape[1] > 1:
        s, w = levels[-1]
        s = np.pad(s, ((0, s.shape[0] % 2), (0, s.shape[1] % 2)))
        w = np.pad(w, ((0, w.shape[0] % 2), (0, w.shape[1] % 2)))
        s = s[0::2, 0::2] + s[1::2, 0::2] + s[0::2, 1::2] + s[1::2, 1::2]
        w = w[0::2, 0::2] + w[1::2, 0::2] + w[0::2, 1::2] + w[1::2, 1::2]
        levels.append((s, w))
    # push: each level's empty texels take the coarser level's average
    s, w = levels[-1]
    estimate = s / np.maximum(w, 1e-300)
    for s, w in reversed(levels[:-1]):
        up = np.repeat(np.repeat(estimate, 2, axis=0), 2, axis=1)[: s.shape[0], : s.shape[1]]
        estimate = np.where(w > 0, s / np.maximum(w, 1e-300), up)
    return np.where(weight > 0, values, estimate)
