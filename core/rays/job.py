"""The rays of a bake, scheduled: :class:`AOJob` computes every target's AO one batch per step.

Targets are the texels of a layout or free points (:mod:`.targets`).
Batches are sized to take about :data:`STEP_SECONDS`, so a caller polling
between steps (ESC in Blender's UI) never waits long; the adaptive stop asks
each texel's atlas neighbours too (see :func:`.ao.settle_pilot`).
"""

import time
from typing import NamedTuple

import numpy as np

from .ao import buried_by_vote, occlusion_sums, settle_pilot
from .cycles_rules import BULK_PILOT_RAYS
from .ray_setup import RayPart, adaptive_pilot_rays
from .targets import PointTargets

#: Target duration of one :meth:`AOJob.step` (seconds).
STEP_SECONDS = 0.3

#: Target duration of one step of rays handed to a caster's ``ambient_occlusion`` (seconds; each call
#: has a fixed cost of its own: Cycles syncs the scene and builds its BVH).
BULK_STEP_SECONDS = 1.5
#: Rays of the first such step (the next ones are sized by how long it took).
BULK_FIRST_RAYS = 1 << 20
#: A part (input mesh) with fewer rays than this left after its pilot gets them ray by ray instead: each
#: ``ambient_occlusion`` call has a fixed cost (Cycles: scene sync and BVH, about 0.01-0.04 s, and a few
#: microseconds per texel), which on a small part buys nothing, and a bake of many small objects
#: would pay it once per object per step.
BULK_LEAST_RAYS = 1 << 18


#: No texel gets fewer rays than this when its share is cut.
MIN_SHARED_RAYS = 4


class RayPass(NamedTuple):
    """Some texels' rays, cast in one go (in batches) before the job moves on to the next pass."""

    texels: np.ndarray              # (k,) int, target indices, in casting order
    rays: np.ndarray                # (r,) int, which of each texel's ray directions
    given: tuple = None             # (points, normals, geometric) (k, 3) each, where not the targets' own
    whole: bool = False             # handed to the casters' ambient_occlusion (whole texels), not ray by ray


class AOJob:
    """AO of every target (the texels of a layout, or points), computed one batch per :meth:`step`.

    Two phases: the pilot rays for every texel, then the remaining rays for
    the texels that cannot stop early (see :mod:`.ao`: a texel stops when its
    pilot rays and all its atlas neighbours' agree).  The operator calls
    :meth:`step` once per timer event (each batch is about ``batch_rays``
    rays, a fraction of a second), so it can draw progress and react to ESC
    between batches.

    When every part's caster can shade whole texels itself
    (:attr:`.ray_setup.RayCaster.bakes_whole_texels`, its ``ambient_occlusion``: the
    Blender side's Cycles caster), each texel's first
    :data:`BULK_PILOT_RAYS` rays are cast ray by ray (they tell which texels
    are buried; the rays that find the creases are too, right after them),
    and the remaining rays of every texel, and all rays at the creases, are
    left to that method, in steps of about :data:`BULK_STEP_SECONDS`, with no
    adaptive stop (such a caster's rays cost a fraction of the pilot's).  A
    part with fewer than :data:`BULK_LEAST_RAYS` rays after such a pilot is
    cast as if its caster could not: its own pilot, the adaptive stop, ray by
    ray.

    A target's share of the rays may be halved (:meth:`.targets.TexelTargets.shares`):
    a padding ring texel's always, and with ``weighted`` rays a texel's in
    proportion to the blend weight it is shown with (:func:`.targets.ray_shares`).
    Texels of one share form a class with its own ray count and pilot, each a
    stratified prefix of the same sequence.

    Parameters
    ----------
    targets : TexelTargets or PointTargets
    parts : list of RayPart, one per input mesh (all with the same ray count)
    batch_rays : int
    weighted : bool

    Attributes, when :attr:`finished`
    ---------------------------------
    ao : (n,) float32 per texel
    computed : (n,) bool, texels that got rays
    settled : (n,) bool, texels the adaptive stop settled after their pilot rays
    buried : (n,) bool, computed texels inside a closed piece (:func:`.ao.buried_by_vote`),
        but for the rim of each buried region, which is shaded again at the
        crease (:meth:`_queue_creases`)
    ray_count : (n,) int, rays each texel was meant to get
    """

    def __init__(self, targets, parts, batch_rays=1 << 19, weighted=False):
        self.targets = targets
        self.parts = parts
        count = targets.count
        self.computed = targets.computed
        self.total = int(self.computed.sum())
        self.ao = np.zeros(count, dtype=np.float32)
        self.sums = np.zeros(count, dtype=np.float64)
        self.behind = np.zeros(count, dtype=np.int64)            # rays that hit a back face
        self.cast_count = np.zeros(count, dtype=np.int64)        # rays cast
        self.buried = np.zeros(count, dtype=bool)
        self.settled = np.zeros(count, dtype=bool)
        self.at_crease = np.zeros(count, dtype=bool)            # shaded at a crease found before the bulk
        self.creased = False
        self.rays_cast = 0
        self.seconds = 0.0
        self.params = parts[0].params
        self.batch_rays = batch_rays
        self.bulk = all(part.caster.bakes_whole_texels for part in parts)
        self.bulk_rays = BULK_FIRST_RAYS
        selected = targets.casting_order(np.flatnonzero(self.computed))
        halvings = targets.shares(self.computed, weighted)[selected]
        rays = self.params.rays
        self.whole_parts = self._whole_texel_parts(selected, shared_rays(rays, halvings))
        whole = self.whole_parts[targets.part_of(selected)]
        self.ray_count = np.zeros(count, dtype=np.int64)
        self.pilot_count = np.zeros(count, dtype=np.int64)
        self.passes = []                     # RayPass, in casting order
        self.remaining = []                  # per class: its RayPass after the pilot (not yet thinned)
        for halving in np.unique(halvings):
            for by_whole in (True, False):
                members = selected[(halvings == halving) & (whole == by_whole)]
                if not len(members):
                    continue
                count = int(shared_rays(rays, halving))
                pilot = min(count, BULK_PILOT_RAYS) if by_whole else adaptive_pilot_rays(count, self.params.adaptive)
                self.ray_count[members] = count
                self.pilot_count[members] = pilot
                self.passes.append(RayPass(members, np.arange(pilot)))
                self.remaining.append(RayPass(members, np.arange(pilot, count), whole=by_whole))
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

    @property
    def seen(self):
        """(n,) bool: the texels that got rays and are not buried (their AO means something)."""
        return self.computed & ~self.buried

    def noise_texels(self):
        """(n,) bool: the texels whose rays tell their variance: seen, and not settled by the adaptive stop
        (which says nothing of it) unless their pilot was all their rays."""
        return self.seen & ~(self.settled & (self.pilot_count < self.ray_count))

    def caster_name(self):
        """The name of the caster that cast the rays: the first part's, or its pilot's where it bakes whole
        texels but no part had rays enough to be given any (they were all cast as its pilot)."""
        first = self.parts[0].caster
        return first.name if self.whole_parts.any() else first.pilot_name

    def step(self):
        """Compute the next batch; returns the fraction done."""
        if self.finished:
            return 1.0
        start = time.perf_counter()
        queue, rays = self.passes[0].texels, self.passes[0].rays
        if self.passes[0].whole:
            return self._bulk_step(start)
        batch = queue[self.position:self.position + max(1, self.batch_rays // max(len(rays), 1))]
        for selection, ray_part, (points, normals, geometric) in self._batch_by_part(batch, self.passes[0].given):
            sums, behind = occlusion_sums(points, normals, geometric, self.targets.ids[selection], rays,
                                          ray_part.params, ray_part.caster)
            self.sums[selection] += sums
            self.behind[selection] += behind
            self.cast_count[selection] += len(rays)
        # Aim at STEP_SECONDS per step, so a caller polling between steps
        # (ESC in the UI) never waits long, without a step per thousand rays.
        self.batch_rays = self._next(queue, len(batch), len(rays), start, self.batch_rays, STEP_SECONDS, 1 << 23)
        return self.fraction

    def _next(self, queue, texels, rays, start, batch_rays, seconds, most):
        """After a batch of ``texels`` x ``rays`` of ``queue``: on to the next pass when it is done, the AO
        when all are; returns the rays of the next batch (``batch_rays`` scaled to take about ``seconds``,
        at most 4x up or down and within 2^16..``most``)."""
        self.rays_cast += texels * rays
        self.work_done += texels * rays
        self.position += texels
        elapsed = time.perf_counter() - start
        if elapsed > 0:
            wanted = batch_rays * seconds / elapsed
            batch_rays = int(min(max(wanted, batch_rays / 4, 1 << 16), batch_rays * 4, most))
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
        return batch_rays

    def _bulk_step(self, start):
        """A batch of texels' remaining rays, shaded by their parts' casters' ``ambient_occlusion``."""
        queue, samples = self.passes[0].texels, len(self.passes[0].rays)
        batch = queue[self.position:self.position + max(1, self.bulk_rays // max(samples, 1))]
        at_own_points = self.passes[0].given is None
        for selection, ray_part, (points, normals, geometric) in self._batch_by_part(batch, self.passes[0].given):
            open_fraction = ray_part.caster.ambient_occlusion(points, normals, geometric, samples, ray_part.params)
            occluded = (1.0 - np.clip(np.nan_to_num(open_fraction), 0.0, 1.0)) * samples
            if at_own_points:
                occluded[self.at_crease[selection]] = 0.0        # shaded at its crease instead
            self.sums[selection] += occluded
        self.bulk_rays = self._next(queue, len(batch), samples, start, self.bulk_rays, BULK_STEP_SECONDS, 1 << 26)
        return self.fraction

    def _batch_by_part(self, batch, where):
        """Per part among the texels ``batch`` (the current pass's from :attr:`position`): its texels, its
        :class:`RayPart` and their point, shading and geometric normal (k, 3) in its ray space, from the
        targets or from the pass's given points ``where`` (the creases)."""
        part_of = self.targets.part_of(batch)
        if where is not None:
            where = tuple(given[self.position:self.position + len(batch)] for given in where)
        for part in np.unique(part_of):
            mine = part_of == part
            ray_part = self.parts[part]
            if where is None:
                yield batch[mine], ray_part, self._ray_geometry(ray_part, batch[mine])
            else:
                yield batch[mine], ray_part, tuple(given[mine] for given in where)

    def _queue_creases(self):
        """Find the buried texels; queue the rim of each buried region to be shaded again at the crease.

        A texel beside a visible one of its chart is read by bilinear
        filtering at visible points within a texel of where its piece enters
        the other (a crease: Suzanne's eye meeting her head, a crate standing
        on the floor).  Its own point is inside the other piece (AO 0: a dark
        line), so it is shaded at the crease instead: the point where a ray
        from its visible neighbour's point towards its own first meets the
        other piece, which is the last visible point between them.  Deeper
        buried texels keep their AO (never read at a visible point).  Returns the rim texels (k,) int.
        """
        self.creased = True
        computed = self.computed
        self.buried[computed] = buried_by_vote(self.behind[computed], np.maximum(self.cast_count[computed], 1),
                                               self.params)
        rim, donor = self.targets.rim(self.buried, computed)
        if not len(rim):
            return rim
        part_of = self.targets.part_of(rim)
        order = np.lexsort((self.targets.ids[rim], part_of))
        rim, donor, part_of = rim[order], donor[order], part_of[order]
        points = np.empty((len(rim), 3))
        normals, geometric = np.empty_like(points), np.empty_like(points)
        for part in np.unique(part_of):
            mine = np.flatnonzero(part_of == part)
            ray_part = self.parts[part]
            own, normals[mine], geometric[mine] = self._ray_geometry(ray_part, rim[mine])
            points[mine] = crease_points(*self._ray_geometry(ray_part, donor[mine]), own, ray_part.params,
                                         ray_part.caster)
        self.buried[rim] = False
        self.sums[rim] = 0.0
        self.ray_count[rim] = self.params.rays
        # a part whose rays go to ambient_occlusion sends its creases there too (given points, same origins)
        whole = self.whole_parts[part_of]
        for by_whole in (True, False):
            mine = whole == by_whole
            if mine.any():
                self.passes.append(RayPass(rim[mine], np.arange(self.params.rays),
                                           (points[mine], normals[mine], geometric[mine]), by_whole))
        self.work_expected = self.work_done + len(rim) * self.params.rays
        return rim

    def _ray_geometry(self, ray_part, selection):
        """Point, shading normal and geometric normal (k, 3) of some targets, in their part's ray space."""
        points, normals, geometric = self.targets.geometry(selection)
        points, normals = ray_part.to_ray(points, normals)
        return points, normals, ray_part.to_ray(points, geometric)[1]

    def _after_pilot(self):
        """Decide which texels stop early (all classes together); queue the rest for their remaining rays."""
        self.pilot = False
        ask = self.targets.neighbours_agree
        # the adaptive stop, for the texels whose parts keep their rays ray by ray
        stoppable = [remaining.texels for remaining in self.remaining if not remaining.whole]
        if stoppable:
            selection = np.concatenate(stoppable)
            sums = self.sums[selection]                  # settle_pilot scales the sums of the texels it stops
            decided = settle_pilot(sums, self.params, self.pilot_count[selection],
                                   neighbours=None if ask is None else (lambda code: ask(selection, code)),
                                   rays=self.ray_count[selection])
            self.sums[selection] = sums
            self.settled[selection[decided]] = True
        # Where every part bakes whole texels, only the pilot's rays can tell the buried texels (Cycles' AO
        # cannot), so the creases are found now, and no single ray is cast after this: the casters may let go
        # of what casting them needs (the Cycles caster: Blender's BVH of the occluders, beside which Cycles
        # would build its own).  The rim texels, shaded again at the crease, stay in the bulk's batches (so
        # every other texel gets the same Cycles pixel, and samples, as with the creases found last), but
        # what the bulk finds at their own points is not counted.
        crease_passes = []
        if len(self.parts) and self.whole_parts.all():
            before = len(self.passes)
            self.at_crease[self._queue_creases()] = True
            crease_passes, self.passes = self.passes[before:], self.passes[:before]
            for part in self.parts:
                part.caster.casting_done()
        for remaining in self.remaining:
            todo = remaining.texels[~self.settled[remaining.texels]]
            if len(remaining.rays) and len(todo):
                self.passes.append(remaining._replace(texels=todo))
        self.passes += crease_passes
        self.remaining = []
        self.work_expected = self.work_done + sum(len(p.texels) * len(p.rays) for p in self.passes)

    def _whole_texel_parts(self, selected, counts):
        """(parts,) bool: the parts whose rays after the pilot go to their caster's ``ambient_occlusion``:
        when the job is :attr:`bulk`, those with at least :data:`BULK_LEAST_RAYS` such rays among the texels
        ``selected`` (k,) int, which get ``counts`` (k,) int rays each; none otherwise."""
        left = np.maximum(counts - BULK_PILOT_RAYS, 0)
        per_part = np.bincount(self.targets.part_of(selected), weights=left, minlength=len(self.parts))
        return (per_part >= BULK_LEAST_RAYS) & self.bulk


def shared_rays(rays, halvings):
    """Rays of a texel whose share of ``rays`` is halved ``halvings`` times (int or (k,) int), never below
    :data:`MIN_SHARED_RAYS` (nor above ``rays``)."""
    return np.minimum(rays, np.maximum(MIN_SHARED_RAYS, np.right_shift(rays, halvings)))


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


def point_ao(points, normals, geometric, params, caster, ids=None):
    """AO of free points in ray space, scheduled as a bake's texels are (:class:`AOJob`), without neighbours.

    Parameters
    ----------
    points, normals, geometric : (k, 3) float64
    params : AOParams
    caster : RayCaster
    ids : (k,) int, optional, stable ids (the per-point scramble; default 0..k-1)

    Returns
    -------
    ao : (k,) float32 in [0, 1]
    rays_cast : int
    """
    job = AOJob(PointTargets(points, normals, geometric, ids), [RayPart(params, caster)])
    while not job.finished:
        job.step()
    return job.ao, job.rays_cast
