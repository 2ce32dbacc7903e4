"""The rays of a bake, scheduled: :class:`AOJob` computes every texel's AO one batch per step.

Batches are sized to take about :data:`STEP_SECONDS`, so a caller polling
between steps (ESC in Blender's UI) never waits long; the adaptive stop asks
each texel's atlas neighbours too (see :func:`.ao.settle_pilot`).
"""

import time

import numpy as np

from .ao import buried, occlusion_sums, pilot_rays, settle_pilot
from .grid import neighbour_values
from .raster import texel_geometry

#: Target duration of one :meth:`AOJob.step` (seconds).
STEP_SECONDS = 0.3


#: Rays of a texel seen with blend weight w: the full count for w > 1/2, half for w in (1/4, 1/2], ...,
#: down to 1 / 2**MAX_RAY_HALVINGS of it (see :func:`ray_shares`).
MAX_RAY_HALVINGS = 3
#: No texel gets fewer rays than this when its share is cut.
MIN_SHARED_RAYS = 4


class AOJob:
    """AO of every texel of a layout, computed one batch per :meth:`step`.

    Two phases: the pilot rays for every texel, then the remaining rays for
    the texels that cannot stop early (see :mod:`.ao`: a texel stops when its
    pilot rays and all its atlas neighbours' agree).  The operator calls
    :meth:`step` once per timer event (each batch is about ``batch_rays``
    rays, a fraction of a second), so it can draw progress and react to ESC
    between batches.

    With ``weighted`` rays, a texel gets rays in proportion to the blend
    weight it is shown with (:func:`ray_shares`): texels of one share form a
    class with its own ray count and pilot, each a stratified prefix of the
    same sequence.

    Parameters
    ----------
    layout : Layout
    parts : list of ``(params, caster, to_ray)``, one per input mesh
        :class:`.ao.AOParams` (all with the same ray count), a caster (see
        :mod:`.ao`), and the mapping to that mesh's ray space from
        :func:`.ao.ray_space`.
    batch_rays : int
    ray_rings : int
        Padding rings that get rays of their own (bilinear filtering reads
        only covered and near texels; farther rings are filled from their
        neighbours by :func:`texel_image`, which is what mip-maps need).
    weighted : bool

    Attributes, when :attr:`finished`
    ---------------------------------
    ao : (n,) float32 per texel
    computed : (n,) bool, texels that got rays
    buried : (n,) bool, computed texels inside a closed piece (:func:`.ao.buried`),
        but for the rim of each buried region, which is shaded again at the
        crease (:meth:`_queue_creases`)
    ray_count : (n,) int, rays each texel was meant to get
    """

    def __init__(self, layout, parts, batch_rays=1 << 19, ray_rings=1, weighted=False):
        self.layout = layout
        self.parts = parts
        texels = layout.texels
        self.computed = texels.ring <= ray_rings
        self.total = int(self.computed.sum())
        self.ao = np.zeros(len(texels), dtype=np.float32)
        self.sums = np.zeros(len(texels), dtype=np.float64)
        self.behind = np.zeros(len(texels), dtype=np.int64)     # rays that hit a back face
        self.cast_count = np.zeros(len(texels), dtype=np.int64)  # rays cast
        self.buried = np.zeros(len(texels), dtype=bool)
        self.creased = False
        self.rays_cast = 0
        self.seconds = 0.0
        self.params = parts[0][0]
        self.batch_rays = batch_rays
        selected = np.flatnonzero(self.computed)
        # texels of one part together, in atlas order inside each part
        selected = selected[np.lexsort((texels.index[selected], layout.part_of_texel(selected)))]
        halvings = np.zeros(len(selected), dtype=np.int64)
        if weighted:
            halvings = ray_shares(layout, self.computed)[selected]
        rays = self.params.rays
        self.ray_count = np.zeros(len(texels), dtype=np.int64)
        self.pilot_count = np.zeros(len(texels), dtype=np.int64)
        self.passes = []                     # [texels, ray indices], in casting order
        self.remaining = []                  # per class: (its texels, its ray indices after the pilot)
        for halving in np.unique(halvings):
            members = selected[halvings == halving]
            count = min(rays, max(MIN_SHARED_RAYS, rays >> int(halving)))
            pilot = pilot_rays(count, self.params.adaptive)
            self.ray_count[members] = count
            self.pilot_count[members] = pilot
            self.passes.append([members, np.arange(pilot), None])
            self.remaining.append((members, np.arange(pilot, count)))
        self.pilot = True
        self.position = 0
        self.work_done = 0
        self.work_expected = int(self.ray_count[selected].sum())

    @property
    def finished(self):
        return not self.passes

    @property
    def fraction(self):
        return min(1.0, self.work_done / max(self.work_expected, 1)) if not self.finished else 1.0

    def step(self):
        """Compute the next batch; returns the fraction done."""
        if self.finished:
            return 1.0
        start = time.perf_counter()
        queue, rays, where = self.passes[0]
        stop = self.position + max(1, self.batch_rays // max(len(rays), 1))
        batch = queue[self.position:stop]
        part_of = self.layout.part_of_texel(batch)
        for part in np.unique(part_of):
            selection = batch[part_of == part]
            params, caster, to_ray = self.parts[part]
            if where is None:
                points, normals, geometric = self._ray_geometry(to_ray, selection)
            else:                                    # given points, in ray space (the creases)
                points, normals, geometric = (a[self.position:stop][part_of == part] for a in where)
            sums, behind = occlusion_sums(
                points, normals, geometric, self.layout.texels.index[selection], rays, params, caster)
            self.sums[selection] += sums
            self.behind[selection] += behind
            self.cast_count[selection] += len(rays)
        self.rays_cast += len(batch) * len(rays)
        self.work_done += len(batch) * len(rays)
        self.position += len(batch)
        # Aim at STEP_SECONDS per step, so a caller polling between steps
        # (ESC in the UI) never waits long, without a step per thousand rays.
        elapsed = time.perf_counter() - start
        if elapsed > 0:
            wanted = self.batch_rays * STEP_SECONDS / elapsed
            self.batch_rays = int(min(max(wanted, self.batch_rays / 4, 1 << 16), self.batch_rays * 4, 1 << 23))
        if self.position >= len(queue):
            self.passes.pop(0)
            self.position = 0
            if self.pilot and not self.passes:
                self._after_pilot()
            if not self.passes and not self.creased:
                self._queue_creases()
        if self.finished:
            computed = self.computed
            self.ao[computed] = np.clip(1.0 - self.sums[computed] / self.ray_count[computed], 0.0, 1.0)
        self.seconds += time.perf_counter() - start
        return self.fraction

    def _queue_creases(self):
        """Find the buried texels; queue the rim of each buried region to be shaded again at the crease.

        A texel beside a visible one of its chart is read by bilinear
        filtering at visible points within a texel of where its piece enters
        the other (a crease: Suzanne's eye meeting her head, a crate standing
        on the floor).  Its own point is inside the other piece (AO 0: a dark
        line), so it is shaded at the crease instead: the point where a ray
        from its visible neighbour's point towards its own first meets the
        other piece, which is the last visible point between them.  Deeper
        buried texels keep their AO (never read at a visible point).
        """
        self.creased = True
        computed = self.computed
        self.buried[computed] = buried(self.behind[computed], np.maximum(self.cast_count[computed], 1), self.params)
        texels = self.layout.texels
        rim, donor = buried_rim(texels, self.layout.atlas.member_chart[texels.member], self.buried, computed)
        if not len(rim):
            return
        part_of = self.layout.part_of_texel(rim)
        order = np.lexsort((texels.index[rim], part_of))
        rim, donor, part_of = rim[order], donor[order], part_of[order]
        points = np.empty((len(rim), 3))
        normals, geometric = np.empty_like(points), np.empty_like(points)
        for part in np.unique(part_of):
            mine = np.flatnonzero(part_of == part)
            params, caster, to_ray = self.parts[part]
            own, normals[mine], geometric[mine] = self._ray_geometry(to_ray, rim[mine])
            points[mine] = crease_points(*self._ray_geometry(to_ray, donor[mine]), own, params, caster)
        self.buried[rim] = False
        self.sums[rim] = 0.0
        self.ray_count[rim] = self.params.rays
        self.passes.append([rim, np.arange(self.params.rays), (points, normals, geometric)])
        self.work_expected = self.work_done + len(rim) * self.params.rays

    def _ray_geometry(self, to_ray, selection):
        """Point, shading normal and geometric normal (k, 3) of some texels, in their part's ray space."""
        points, normals, geometric = texel_geometry(self.layout.texels, self.layout.atlas, self.layout.mesh,
                                                    selection)
        points, normals = to_ray(points, normals)
        return points, normals, to_ray(points, geometric)[1]

    def _after_pilot(self):
        """Decide which texels stop early (all classes together); queue the rest for their remaining rays."""
        self.pilot = False
        selection = np.concatenate([members for members, _ in self.remaining])
        sums = self.sums[selection]
        decided = settle_pilot(sums, self.params, self.pilot_count[selection],
                               neighbours=lambda code: neighbours_agree(self.layout.texels, selection, code),
                               rays=self.ray_count[selection])
        self.sums[selection] = sums
        stopped = np.zeros(len(self.layout.texels), dtype=bool)
        stopped[selection[decided]] = True
        for members, rays in self.remaining:
            todo = members[~stopped[members]]
            if len(rays) and len(todo):
                self.passes.append([todo, rays, None])
        self.remaining = []
        self.work_expected = self.work_done + sum(len(todo) * len(rays) for todo, rays, _ in self.passes)


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
    axis = layout.charts.chart_axis[atlas.member_chart] // 2                 # (m,)
    normals = mesh.corner_normals[atlas.member_triangle]                    # (m, 3, 3)
    mean = normals.sum(axis=1)
    candidates = np.concatenate([normals, mean[:, None]], axis=1)           # (m, 4, 3)
    length2 = (candidates * candidates).sum(axis=2)
    component2 = candidates[np.arange(len(axis)), :, axis] ** 2             # (m, 4)
    member_weight = np.max(np.divide(component2, length2, out=np.ones_like(component2), where=length2 > 1e-24), axis=1)
    weight = np.zeros(texels.width * texels.height)
    weight[texels.index[computed]] = member_weight[texels.member[computed]]
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


def crease_points(near, near_normal, near_geometric, far, params, caster):
    """The last visible point on the way from each visible point ``near`` to a buried point ``far``.

    A ray from ``near`` (lifted off its face as rays are) towards ``far``
    meets the piece ``far`` is inside of; the point just before that hit is
    on the visible side of the crease.  Where the ray meets nothing on the way
    (``far`` was buried by its rays' vote, yet nothing lies between), the
    point is ``near`` itself.

    Parameters
    ----------
    near, near_normal, near_geometric, far : (k, 3) float64, ray space
    params : AOParams
    caster : object with ``cast``

    Returns
    -------
    (k, 3) float64
    """
    side = np.where((near_geometric * near_normal).sum(axis=1) < 0.0, -1.0, 1.0)
    start = near + params.offset * near_geometric * side[:, None]
    towards = far - start
    length = np.sqrt((towards * towards).sum(axis=1))
    direction = towards / np.maximum(length, 1e-300)[:, None]
    distance = caster.cast(start, direction, float(length.max()) if len(length) else 0.0)[0]
    travel = np.where(np.isfinite(distance) & (distance <= length), np.maximum(distance - params.offset, 0.0), 0.0)
    return start + direction * travel[:, None]
