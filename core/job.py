"""The rays of a bake, scheduled: :class:`AOJob` computes every texel's AO one batch per step.

Batches are sized to take about :data:`STEP_SECONDS`, so a caller polling
between steps (ESC in Blender's UI) never waits long; the adaptive stop asks
each texel's atlas neighbours too (see :func:`.ao.settle_pilot`).
"""

import time

import numpy as np

from .ao import occlusion_sums, pilot_rays, settle_pilot
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
    """

    def __init__(self, layout, parts, batch_rays=1 << 19, ray_rings=1, weighted=False):
        self.layout = layout
        self.parts = parts
        texels = layout.texels
        self.computed = texels.ring <= ray_rings
        self.total = int(self.computed.sum())
        self.ao = np.zeros(len(texels), dtype=np.float32)
        self.sums = np.zeros(len(texels), dtype=np.float64)
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
            self.passes.append([members, np.arange(pilot)])
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
        queue, rays = self.passes[0]
        batch = queue[self.position:self.position + max(1, self.batch_rays // max(len(rays), 1))]
        part_of = self.layout.part_of_texel(batch)
        for part in np.unique(part_of):
            selection = batch[part_of == part]
            params, caster, to_ray = self.parts[part]
            points, normals, geometric = texel_geometry(
                self.layout.texels, self.layout.atlas, self.layout.mesh, selection)
            points, normals = to_ray(points, normals)
            _, geometric = to_ray(points, geometric)
            self.sums[selection] += occlusion_sums(
                points, normals, geometric, self.layout.texels.index[selection], rays, params, caster)
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
        if self.finished:
            computed = self.computed
            self.ao[computed] = np.clip(1.0 - self.sums[computed] / self.ray_count[computed], 0.0, 1.0)
        self.seconds += time.perf_counter() - start
        return self.fraction

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
                self.passes.append([todo, rays])
        self.remaining = []
        self.work_expected = self.work_done + sum(len(todo) * len(rays) for todo, rays in self.passes)


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
    grid = np.pad(weight.reshape(texels.height, texels.width), 1)
    near = grid[1:-1, 1:-1].copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            near = np.maximum(near, grid[1 + dy:1 + dy + texels.height, 1 + dx:1 + dx + texels.width])
    texel_weight = near.ravel()[texels.index]
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
    width, height = texels.width, texels.height
    grid = np.full((height + 2) * (width + 2), _NO_VOTE, dtype=np.int8)
    index = texels.index[selection]
    x, y = index % width + 1, index // width + 1
    grid[y * (width + 2) + x] = code
    agree = np.ones(len(selection), dtype=bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dx or dy:
                other = grid[(y + dy) * (width + 2) + x + dx]
                agree &= (other == code) | (other == _NO_VOTE)
    return agree
