"""Edge-aware denoising of AO in texel space (Cycles cannot denoise an AO bake).

A joint bilateral filter over each texel's atlas neighbours, guided by what
the texels sample: neighbours count only if they are in the same chart, near
in 3D (object units, so a chart stretched at a grazing angle is not blurred
along the stretch), face the same way (a crease stops it) and agree with the
texel's value within the noise the ray count leaves (a contact shadow stops
it).  Work goes band by band over the image rows, so memory stays linear in
the band, not the image.

How near counts is a Gaussian of the 3D distance, one texel wide in a bake
of many rays.  A bake of a few rays per texel has so much noise left that a
wider Gaussian lowers the error more than its blur raises it, so the width
grows as the rays get fewer (:func:`space_sigma_for`), within a window of at
most :data:`MAX_RADIUS` texels each side (tests/bench/bench_denoise.py).
"""

import numpy as np

from ..atlas.raster import texel_geometry

#: Texel positions are clipped to this distance from the origin (object units) before float32
#: distances are squared (squares up to 1.2e37, under float32's 3.4e38).
FARTHEST = 1.0e18
#: Rows of texels filtered at once.
BAND_ROWS = 256
#: Width of the distance weight, in texels, with many rays per texel (from 8 on).
SPACE_SIGMA = 1.0
#: Width of the distance weight, in texels, with one ray per texel; it narrows as one over the square root of
#: the rays.  At 256² and 512², 1 to 4 rays, it lowered the RMSE on the four report meshes, most on the smooth
#: ones, and cost the interior 1% at 256², 4 rays (tests/bench/bench_denoise.py).
ONE_RAY_SPACE_SIGMA = 2.8
#: Texels each side of the filter's window, at least.
RADIUS = 2
#: Texels each side of the filter's window, at most: a 7x7 window weighs twice the pairs of a 5x5 one (24
#: against 12), a 9x9 one over three times.
MAX_RADIUS = 3
#: The window reaches this many widths each side, rounded up, within RADIUS and MAX_RADIUS.
WINDOW_SIGMAS = 1.65


def space_sigma_for(rays):
    """Width (texels) of the distance weight for a bake of at most ``rays`` rays per texel:
    ``ONE_RAY_SPACE_SIGMA / sqrt(rays)``, never under :data:`SPACE_SIGMA` (from 8 rays on)."""
    return max(SPACE_SIGMA, ONE_RAY_SPACE_SIGMA / np.sqrt(max(float(rays), 1.0)))


def window_radius(space_sigma):
    """Texels each side of the window for a distance weight ``space_sigma`` texels wide."""
    return int(min(MAX_RADIUS, max(RADIUS, np.ceil(WINDOW_SIGMAS * space_sigma - 1e-9))))


def denoise(texels, atlas, mesh, values, computed, rays, radius=None, space_sigma=None, normal_power=16.0,
            range_sigmas=2.5, geometry=None):
    """Filtered AO values.

    Parameters
    ----------
    texels : Texels
    atlas : Atlas
    mesh : TriangleMesh
    values : (n,) float AO of every texel (only ``computed`` ones are used)
    computed : (n,) bool
    rays : int or (n,) int, rays per texel (sets the expected noise)
    radius : int, texels each side; by default :func:`window_radius` of the width
    space_sigma : float, Gaussian width of the 3D distance weight, in texels; by default
        :func:`space_sigma_for` the most rays a computed texel has
    normal_power : float, exponent of the normal agreement (n_i . n_j)
    range_sigmas : float, value differences beyond this many noise sigmas do not blend
    geometry : callable, optional
        ``selection -> (points, normals, geometric)`` of ``computed`` texels (the bake's
        :meth:`..rays.targets.TexelTargets.geometry`, which may have them already); by default
        :func:`..atlas.raster.texel_geometry`.

    Returns
    -------
    (n,) float32, equal to ``values`` where not ``computed``.
    """
    width, height = texels.width, texels.height
    if space_sigma is None:
        most_rays = np.max(np.asarray(rays)[computed] if np.ndim(rays) else rays, initial=1)
        space_sigma = space_sigma_for(most_rays)
    radius = window_radius(space_sigma) if radius is None else int(radius)
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
        points, normals, _ = (texel_geometry(texels, atlas, mesh, halo) if geometry is None else geometry(halo))
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
        # One plane per coordinate: sums over a trailing axis of 3 are slow in numpy.
        # clipped where float32 squares of differences would overflow (stray vertices 10^18 out)
        point = [grid(np.clip(points[:, k], -FARTHEST, FARTHEST).astype(np.float32), 0.0, np.float32)
                 for k in range(3)]
        normal = [grid(normals[:, k].astype(np.float32), 0.0, np.float32) for k in range(3)]
        # noise of an AO estimate from ``rays`` rays (binomial), floored at one ray's worth
        count = grid(np.broadcast_to(np.asarray(rays, dtype=np.float32), values.shape)[halo], 1.0, np.float32)
        variance = np.maximum(value * (1.0 - value), 1.0 / count) / count

        # The weight of a pair of texels does not depend on which one is the
        # centre, so each pair is weighed once and added to both ends.
        weight_sum = np.zeros(shape, dtype=np.float32)
        value_sum = np.zeros(shape, dtype=np.float32)
        for dy, dx in _half_window(radius):
            here, there = _pair_slices(shape, dy, dx)
            usable = valid[here] & valid[there] & (chart[here] == chart[there])
            distance2 = sum((plane[there] - plane[here]) ** 2 for plane in point)
            facing = np.clip(sum(plane[there] * plane[here] for plane in normal), 0.0, 1.0)
            facing = _power(facing, normal_power)
            spread = range_sigmas**2 * (variance[here] + variance[there])
            weight = np.exp(-0.5 * distance2 / sigma_space**2 - 0.5 * (value[there] - value[here]) ** 2 / spread)
            weight *= facing * usable
            weight_sum[here] += weight
            weight_sum[there] += weight
            value_sum[here] += weight * value[there]
            value_sum[there] += weight * value[here]
        inner = (slice(radius, radius + grid_rows), slice(radius, radius + width))
        filtered = (value[inner] + value_sum[inner]) / (1.0 + weight_sum[inner])
        own = computed & (rows >= band_start) & (rows < band_stop)
        own_index = np.flatnonzero(own)
        local = texels.index[own_index] - top * width
        out[own_index] = filtered[local // width, local % width]
    return out


def _half_window(radius):
    """Offsets (dy, dx) of one half of a (2r+1)² window: each unordered pair of texels once."""
    return [(dy, dx) for dy in range(0, radius + 1) for dx in range(-radius, radius + 1) if dy > 0 or dx > 0]


def _pair_slices(shape, dy, dx):
    """Slices ``here`` and ``there`` of a (rows, cols) grid with ``there`` = ``here`` + (dy, dx), dy >= 0."""
    rows, cols = shape[:2]
    here = (slice(0, rows - dy), slice(max(0, -dx), cols - max(0, dx)))
    there = (slice(dy, rows), slice(max(0, dx), cols - max(0, -dx)))
    return here, there


def _power(base, exponent):
    """``base ** exponent``, by repeated squaring when the exponent is a power of two (the default 16)."""
    steps = np.log2(exponent) if exponent >= 1 else -1.0
    if steps == int(steps):
        for _ in range(int(steps)):
            base = base * base
        return base
    return base**exponent
