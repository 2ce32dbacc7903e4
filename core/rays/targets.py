"""What a bake's rays are cast for: the texels of a layout (:class:`TexelTargets`), or free points
(:class:`PointTargets`: the crease tests, :func:`.job.point_ao`).

:class:`.job.AOJob` schedules rays for any target set; the set says which
targets get rays, in what order, where each one's surface point and normals
are, which of them are neighbours (the adaptive stop asks them), how strongly
each is shown (weighted rays), and which buried targets border seen ones (the
crease pass).
"""

import numpy as np

from ..arrays.grid import neighbour_values
from ..atlas.raster import texel_geometry

#: Up to this many texels, their points and normals are computed once and kept for the bake (72 bytes
#: each, 19 MB at most): the pilot, the remaining rays, the crease pass and the denoiser all read them.
#: Above it each batch computes its own, so memory stays linear in the batch.
GEOMETRY_CACHE_TEXELS = 1 << 18

#: Padding-ring texels that get rays (ring 1) have their share halved once more: no point of a chart reads
#: them, they serve the denoiser (as neighbours of rim texels) and the mip-maps.  With no rays at all the
#: rim texels lost their denoising and long_thin's RMSE at 512²/32 rose from 0.0271 to 0.0305; with half
#: the rays it was 0.0270 (tests/bench/bench_rings.py).
RING_RAY_HALVINGS = 1

#: Rays of a texel seen with blend weight w: the full count for w > 1/2, half for w in (1/4, 1/2], ...,
#: down to 1 / 2**MAX_RAY_HALVINGS of it (see :func:`ray_shares`).
MAX_RAY_HALVINGS = 3


class TexelTargets:
    """The texels of a :class:`..layout.Layout` as ray targets.

    Parameters
    ----------
    layout : Layout
    ray_rings : int
        Padding rings that get rays of their own (bilinear filtering reads
        only covered and near texels; farther rings are filled from their
        neighbours by :func:`..image.fill.texel_image`, which is what mip-maps need).
    """

    def __init__(self, layout, ray_rings=1):
        self.layout = layout
        texels = layout.texels
        self.count = len(texels)
        self.computed = texels.ring <= ray_rings                 # (n,) bool: targets that get rays
        self.ids = texels.index                                  # (n,) stable ids: the per-texel scramble
        self._geometry = None                                    # (points, normals, geometric) when kept

    def part_of(self, selection):
        """(k,) int: the input mesh of each selected texel."""
        return self.layout.part_of_texel(selection)

    def casting_order(self, selection):
        """``selection`` reordered for casting: the texels of one part together, in atlas order inside each."""
        return selection[np.lexsort((self.ids[selection], self.part_of(selection)))]

    def geometry(self, selection):
        """Surface point, shading normal and geometric normal (k, 3) of some texels that get rays, in object
        space (kept after the first call, up to :data:`GEOMETRY_CACHE_TEXELS` texels)."""
        layout = self.layout
        if self.count > GEOMETRY_CACHE_TEXELS:
            return texel_geometry(layout.texels, layout.atlas, layout.mesh, selection)
        if self._geometry is None:
            computed = np.flatnonzero(self.computed)
            self._geometry = tuple(np.zeros((self.count, 3)) for _ in range(3))
            for kept, found in zip(self._geometry, texel_geometry(layout.texels, layout.atlas, layout.mesh, computed)):
                kept[computed] = found
        return tuple(kept[selection] for kept in self._geometry)

    def neighbours_agree(self, selection, code):
        """(k,) bool: every atlas neighbour of each selected texel has its pilot code (:func:`neighbours_agree`)."""
        return neighbours_agree(self.layout.texels, selection, code)

    def shares(self, computed, weighted):
        """(n,) int: how many times each texel's ray count is halved: :data:`RING_RAY_HALVINGS` for a padding
        ring texel, plus, for ``weighted`` rays, for its blend weight (:func:`ray_shares`); never more than
        :data:`MAX_RAY_HALVINGS` in all."""
        halvings = np.where(self.layout.texels.ring > 0, RING_RAY_HALVINGS, 0)
        if weighted:
            halvings = np.minimum(halvings + ray_shares(self.layout, computed), MAX_RAY_HALVINGS)
        return halvings

    def rim(self, buried, computed):
        """The buried texels beside a seen texel of their chart, and one such neighbour each (:func:`buried_rim`)."""
        layout = self.layout
        return buried_rim(layout.texels, layout.atlas.member_chart[layout.texels.member], buried, computed)


class PointTargets:
    """Free points, already in ray space, of one part: no neighbours, no charts, every point shown fully.

    Parameters
    ----------
    points, normals, geometric : (k, 3) float64
    ids : (k,) int, optional, stable ids (the per-point scramble; default 0..k-1)
    """

    def __init__(self, points, normals, geometric, ids=None):
        self.points, self.normals, self.geometric = points, normals, geometric
        self.count = len(points)
        self.computed = np.ones(self.count, dtype=bool)
        self.ids = np.arange(self.count) if ids is None else np.asarray(ids)

    def part_of(self, selection):
        return np.zeros(len(np.arange(self.count)[selection]), dtype=np.int64)

    def casting_order(self, selection):
        return selection

    def geometry(self, selection):
        return self.points[selection], self.normals[selection], self.geometric[selection]

    neighbours_agree = None

    def shares(self, computed, weighted):
        return np.zeros(self.count, dtype=np.int64)

    def rim(self, buried, computed):
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)


def ray_shares(layout, computed):
    """How many times each texel's ray count is halved (0..MAX_RAY_HALVINGS), from the weight it is shown with.

    The node group shows a texel of a chart on axis a with weight n_a² (n the
    unit shading normal), so its noise reaches the screen as w² σ² / N; for a
    fixed number of rays the shown noise is least with N in proportion to w.
    A texel's weight is taken as the largest over the corners of its member
    triangle, the normalised mean of their normals (interpolation can lean
    further toward the axis than any corner), and its 8 atlas neighbours:
    so a texel never gets fewer rays than some point reading it would ask for.

    Returns
    -------
    (n,) int64 per texel (0 where not ``computed``).
    """
    texels, atlas, mesh = layout.texels, layout.atlas, layout.mesh
    # per computed texel, not per member: a million-triangle mesh has far more members than a 256² image texels
    member = texels.member[computed]                                                     # (c,)
    axis = layout.charts.chart_axis[atlas.member_chart[member]] // 2                    # (c,)
    normals = mesh.normals_of(atlas.member_triangle[member])                        # (c, 3, 3)
    mean = normals.sum(axis=1)
    candidates = np.concatenate([normals, mean[:, None]], axis=1)                       # (c, 4, 3)
    length2 = (candidates * candidates).sum(axis=2)
    component2 = candidates[np.arange(len(axis)), :, axis] ** 2                         # (c, 4)
    texel_member_weight = np.max(np.divide(component2, length2, out=np.ones_like(component2), where=length2 > 1e-24),
                                 axis=1)
    weight = np.zeros(texels.width * texels.height)
    weight[texels.index[computed]] = texel_member_weight
    texel_weight = weight[texels.index]
    for other in neighbour_values(weight, texels.index, texels.width, texels.height, 0.0):
        texel_weight = np.maximum(texel_weight, other)
    halvings = np.floor(-np.log2(np.clip(texel_weight, 2.0 ** -MAX_RAY_HALVINGS, 1.0))).astype(np.int64)
    return np.where(computed, np.clip(halvings, 0, MAX_RAY_HALVINGS), 0)


#: Texels without a pilot result (empty or far padding) never veto a neighbour.
_NO_VOTE = 3


def neighbours_agree(texels, selection, code):
    """True where every atlas neighbour (8-neighbourhood) of a texel has the same pilot code.

    Parameters
    ----------
    texels : Texels
    selection : (k,) indices into ``texels`` that have pilot results
    code : (k,) int8 codes from :func:`.ao.pilot_agreement`
    """
    votes = np.full(texels.width * texels.height, _NO_VOTE, dtype=np.int8)
    index = texels.index[selection]
    votes[index] = code
    agree = np.ones(len(selection), dtype=bool)
    for other in neighbour_values(votes, index, texels.width, texels.height, _NO_VOTE):
        agree &= (other == code) | (other == _NO_VOTE)
    return agree


def buried_rim(texels, chart_of_texel, buried_texel, computed):
    """The buried texels beside a seen texel of their chart, each with one such neighbour.

    Parameters
    ----------
    texels : Texels
    chart_of_texel : (n,) int
    buried_texel, computed : (n,) bool

    Returns
    -------
    rim : (k,) int64, indices into ``texels``
    neighbour : (k,) int64, a seen texel of the same chart among each one's 8 neighbours (the 4 sides
        before the corners)
    """
    seen = computed & ~buried_texel
    seen_texel = np.full(texels.width * texels.height, -1, dtype=np.int64)
    seen_texel[texels.index[seen]] = np.flatnonzero(seen)
    candidate = np.flatnonzero(buried_texel & computed)
    neighbour = np.full(len(candidate), -1, dtype=np.int64)
    for other in neighbour_values(seen_texel, texels.index[candidate], texels.width, texels.height, -1):
        take = (neighbour < 0) & (other >= 0)
        take[take] = chart_of_texel[other[take]] == chart_of_texel[candidate[take]]
        neighbour[take] = other[take]
    found = neighbour >= 0
    return candidate[found], neighbour[found]
