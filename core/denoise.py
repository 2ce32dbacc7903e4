"""Edge-aware denoising of AO in texel space (Cycles cannot denoise an AO bake).

A joint bilateral filter over each texel's atlas neighbours, guided by what
the texels sample: neighbours count only if they are in the same chart, near
in 3D (object units, so a chart stretched at a grazing angle is not blurred
along the stretch), face the same way (a crease stops it) and agree with the
texel's value within the noise the ray count leaves (a contact shadow stops
it).  Work goes band by band over the image rows, so memory stays linear in
the band, not the image.
"""

import numpy as np

from .raster import texel_geometry

#: Rows of texels filtered at once.
BAND_ROWS = 256


def denoise(texels, atlas, mesh, values, computed, rays, radius=2, space_sigma=1.0, normal_power=16.0,
            range_sigmas=2.5):
    """Filtered AO values.

    Parameters
    ----------
    texels : Texels
    atlas : Atlas
    mesh : TriangleMesh
    values : (n,) float AO of every texel (only ``computed`` ones are used)
    computed : (n,) bool
    rays : int, rays per texel (sets the expected noise)
    radius : int, texels each side
    space_sigma : float, Gaussian width of the 3D distance weight, in texels
    normal_power : float, exponent of the normal agreement (n_i . n_j)
    range_sigmas : float, value differences beyond this many noise sigmas do not blend

    Returns
    -------
    (n,) float32, equal to ``values`` where not ``computed``.
    """
    width, height = texels.width, texels.height
    out = np.asarray(values, dtype=np.float32).copy()
    rows = texels.index // width
    sigma_space = space_sigma / max(atlas.density, 1e-300)
    chart_of_texel = atlas.member_chart[texels.member]
    for band_start in range(0, height, BAND_ROWS):
        band_stop = min(height, band_start + BAND_ROWS)
        halo = np.flatnonzero(computed & (rows >= band_start - radius) & (rows < band_stop + radius))
        if not len(halo):
            continue
        top = max(0, band_start - radius)
        grid_rows = min(height, band_stop + radius) - top
        points, normals, _ = texel_geometry(texels, atlas, mesh, halo)
        grid_index = texels.index[halo] - top * width
        shape = (grid_rows + 2 * radius, width + 2 * radius)

        def grid(data, fill, dtype):
            array = np.full(shape + data.shape[1:], fill, dtype=dtype)
            y, x = grid_index // width + radius, grid_index % width + radius
            array[y, x] = data
            return array

        value = grid(values[halo], 0.0, np.float32)
        valid = grid(np.ones(len(halo), dtype=bool), False, bool)
        chart = grid(chart_of_texel[halo], -1, np.int64)
        point = grid(points.astype(np.float32), 0.0, np.float32)
        normal = grid(normals.astype(np.float32), 0.0, np.float32)
        # noise of an AO estimate from ``rays`` rays (binomial), floored at one ray's worth
        variance = np.maximum(value * (1.0 - value), 1.0 / rays) / rays

        inner = (slice(radius, radius + grid_rows), slice(radius, radius + width))
        v0, p0, n0, c0, var0 = value[inner], point[inner], normal[inner], chart[inner], variance[inner]
        total = np.ones_like(v0)
        summed = v0.copy()
        for dy in range(-radius, radius + 1):
            for dx in range(-radius, radius + 1):
                if not dx and not dy:
                    continue
                shifted = (slice(radius + dy, radius + dy + grid_rows), slice(radius + dx, radius + dx + width))
                v1 = value[shifted]
                usable = valid[shifted] & (chart[shifted] == c0)
                distance2 = ((point[shifted] - p0) ** 2).sum(axis=-1)
                facing = np.clip((normal[shifted] * n0).sum(axis=-1), 0.0, 1.0) ** normal_power
                spread = range_sigmas**2 * (var0 + variance[shifted])
                weight = np.exp(-0.5 * distance2 / sigma_space**2 - 0.5 * (v1 - v0) ** 2 / spread) * facing
                weight = np.where(usable, weight, 0.0)
                total += weight
                summed += weight * v1
        filtered = summed / total
        own = computed & (rows >= band_start) & (rows < band_stop)
        own_index = np.flatnonzero(own)
        local = texels.index[own_index] - top * width
        out[own_index] = filtered[local // width, local % width]
    return out
