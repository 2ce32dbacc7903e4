"""The rays of a bake, scheduled: :class:`AOJob` computes every texel's AO one batch per step.

Batches are sized to take about :data:`STEP_SECONDS`, so a caller polling
between steps (ESC in Blender's UI) never waits long; the adaptive stop asks
each texel's atlas neighbours too (see :func:`.ao.settle_pilot`).
"""

import time

import numpy as np

from .ao import occlusion_sums, settle_pilot
from .raster import texel_geometry

#: Target duration of one :meth:`AOJob.step` (seconds).
STEP_SECONDS = 0.3


class AOJob:
    """AO of every texel of a layout, computed one batch per :meth:`step`.

    Two passes: the pilot rays for every texel, then the remaining rays for
    the texels that cannot stop early (see :mod:`.ao`: a texel stops when its
    pilot rays and all its atlas neighbours' agree).  The operator calls
    :meth:`step` once per timer event (each batch is about ``batch_rays``
    rays, a fraction of a second), so it can draw progress and react to ESC
    between batches.

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
    """

    def __init__(self, layout, parts, batch_rays=1 << 19, ray_rings=1):
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
        self.queue = selected[np.lexsort((texels.index[selected], layout.part_of_texel(selected)))]
        self.rays = np.arange(self.params.pilot_rays)
        self.position = 0
        self.pilot = True
        self.remaining = np.arange(self.params.pilot_rays, self.params.rays)
        self.work_done = 0
        self.work_expected = self.total * self.params.rays

    @property
    def finished(self):
        return not self.pilot and self.position >= len(self.queue)

    @property
    def fraction(self):
        return min(1.0, self.work_done / self.work_expected) if not self.finished else 1.0

    def step(self):
        """Compute the next batch; returns the fraction done."""
        if self.finished:
            return 1.0
        start = time.perf_counter()
        batch = self.queue[self.position:self.position + max(1, self.batch_rays // max(len(self.rays), 1))]
        part_of = self.layout.part_of_texel(batch)
        for part in np.unique(part_of):
            selection = batch[part_of == part]
            params, caster, to_ray = self.parts[part]
            points, normals, geometric = texel_geometry(
                self.layout.texels, self.layout.atlas, self.layout.mesh, selection)
            points, normals = to_ray(points, normals)
            _, geometric = to_ray(points, geometric)
            self.sums[selection] += occlusion_sums(
                points, normals, geometric, self.layout.texels.index[selection], self.rays, params, caster)
        self.rays_cast += len(batch) * len(self.rays)
        self.work_done += len(batch) * len(self.rays)
        self.position += len(batch)
        # Aim at STEP_SECONDS per step, so a caller polling between steps
        # (ESC in the UI) never waits long, without a step per thousand rays.
        elapsed = time.perf_counter() - start
        if elapsed > 0:
            wanted = self.batch_rays * STEP_SECONDS / elapsed
            self.batch_rays = int(min(max(wanted, self.batch_rays / 4, 1 << 16), self.batch_rays * 4, 1 << 23))
        if self.pilot and self.position >= len(self.queue):
            self._after_pilot()
        if self.finished:
            self.ao[self.computed] = np.clip(1.0 - self.sums[self.computed] / self.params.rays, 0.0, 1.0)
        self.seconds += time.perf_counter() - start
        return self.fraction

    def _after_pilot(self):
        """Decide which texels stop early; queue the rest for the remaining rays."""
        self.pilot = False
        self.position = 0
        if not len(self.remaining):
            self.queue = self.queue[:0]
            return
        sums = self.sums[self.queue]
        decided = settle_pilot(sums, self.params, len(self.rays),
                               neighbours=lambda code: neighbours_agree(self.layout.texels, self.queue, code))
        self.sums[self.queue] = sums
        self.queue = self.queue[~decided]
        self.rays = self.remaining
        self.work_expected = self.work_done + len(self.queue) * len(self.rays)


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
