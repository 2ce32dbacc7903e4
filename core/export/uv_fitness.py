"""Can a UV map hold the AO?  Only if every point of the surface has texels of its own.

A UV map made for colour textures often does not: islands stacked on each
other (mirrored halves, repeated parts), UVs that tile across many units (an
architectural material repeated over a wall), faces collapsed to a line or a
point.  Resampled onto such a map, the AO of one place shows in another.
:func:`uv_fitness` measures each fault as a share of the surface (its 3D
area), so a batch can choose another UV set and say why, and a resample can
refuse with one sentence.
"""

from dataclasses import dataclass

import numpy as np

from ..arrays.geometry2d import cross2d
from ..atlas.raster import covered_rows, expand_spans

#: A fault under this share of the surface does not count (a sliver here and there).
TOLERATED_SHARE = 0.01
#: At most this many texel centres are sampled to find shared UV space (the grid is as fine as that allows).
SAMPLES = 1 << 22
#: The finest grid the shared UV space is looked for on.
FINEST_GRID = 2048


@dataclass
class UVFitness:
    """Shares (0..1) of the surface's area with each fault of a UV map."""

    shared: float        # UV space another face also maps to (stacked or overlapping islands)
    outside: float       # UVs outside the unit square (tiling)
    collapsed: float     # faces with (next to) no UV area
    mirrored: float      # faces mapped mirrored against most of the surface (not a fault alone)

    @property
    def can_hold_ao(self):
        return max(self.shared, self.outside, self.collapsed) < TOLERATED_SHARE

    def problems(self):
        """Sentences for each fault over :data:`TOLERATED_SHARE`, worst first."""
        found = []
        if self.shared >= TOLERATED_SHARE:
            found.append((self.shared, "{:.0%} of the surface shares UV space with other faces".format(self.shared)))
        if self.outside >= TOLERATED_SHARE:
            found.append((self.outside, "{:.0%} of the surface has UVs outside the 0-1 square (the texture tiles "
                                        "there)".format(self.outside)))
        if self.collapsed >= TOLERATED_SHARE:
            found.append((self.collapsed, "{:.0%} of the surface has faces with no UV area".format(self.collapsed)))
        return [sentence for _, sentence in sorted(found, reverse=True)]


def uv_fitness(uv, area):
    """How well a UV map can hold the AO of a surface.

    Parameters
    ----------
    uv : (t, 3, 2) float, the UV of each triangle corner
    area : (t,) float, each triangle's 3D area (what each share is weighted by)

    Returns
    -------
    UVFitness
    """
    uv = np.asarray(uv, dtype=np.float64).reshape(-1, 3, 2)
    area = np.asarray(area, dtype=np.float64)
    total = max(float(area.sum()), 1e-300)
    if not len(uv):
        return UVFitness(0.0, 0.0, 0.0, 0.0)
    signed = 0.5 * cross2d(uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0])
    size = np.abs(signed)
    # collapsed: UV area next to nothing against what the face's 3D area asks of the map's average scale
    scale = float(size.sum()) / total
    collapsed = size <= 1e-6 * scale * area + 1e-20
    outside = (uv.min(axis=1) < -1e-6).any(axis=1) | (uv.max(axis=1) > 1.0 + 1e-6).any(axis=1)
    usable = ~collapsed & ~outside
    majority = np.sign(np.sum(np.sign(signed[usable]) * area[usable])) or 1.0
    mirrored = usable & (np.sign(signed) == -majority)
    fraction = np.zeros(len(uv))
    if usable.any():
        fraction[usable] = _shared_fraction(uv[usable], size[usable])
    return UVFitness(shared=float((fraction * area).sum()) / total,
                     outside=float(area[outside].sum()) / total,
                     collapsed=float(area[collapsed & ~outside].sum()) / total,
                     mirrored=float(area[mirrored].sum()) / total)


def _shared_fraction(uv, size):
    """(k,) the fraction of each triangle's texel centres that another triangle covers too, on a grid as fine
    as :data:`SAMPLES` allows; a triangle with no centre inside takes its centroid's texel."""
    grid = int(min(FINEST_GRID, max(64, np.sqrt(SAMPLES / max(float(size.sum()), 1e-12)))))
    texel_uv = uv * grid
    triangle, row, x_low, x_high = covered_rows(texel_uv, grid, half_open=True)
    first = np.clip(np.ceil(x_low - 0.5), 0, grid).astype(np.int64)
    last = np.clip(np.ceil(x_high - 0.5) - 1, -1, grid - 1).astype(np.int64)
    texels, owners = [], []
    for texel, owner in expand_spans(row, first, last, triangle, grid):
        texels.append(texel)
        owners.append(owner)
    texel = np.concatenate(texels) if texels else np.zeros(0, dtype=np.int64)
    owner = np.concatenate(owners) if owners else np.zeros(0, dtype=np.int64)
    # triangles too small to hold a centre are counted at their centroid
    empty = np.ones(len(uv), dtype=bool)
    empty[owner] = False
    centre = np.clip(np.floor(texel_uv[empty].mean(axis=1)), 0, grid - 1).astype(np.int64)
    texel = np.concatenate([texel, centre[:, 1] * grid + centre[:, 0]])
    owner = np.concatenate([owner, np.flatnonzero(empty)])
    count = np.bincount(texel, minlength=grid * grid)
    shared = np.bincount(owner, weights=(count[texel] > 1).astype(np.float64), minlength=len(uv))
    samples = np.bincount(owner, minlength=len(uv))
    return shared / np.maximum(samples, 1)
