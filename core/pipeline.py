"""The core steps chained: mesh -> charts -> atlas -> texels -> AO image.

Each step is also callable alone (see the modules); this module only orders
them, times them and passes progress and cancellation through.
"""

import time
from dataclasses import dataclass, field

import numpy as np

from .adjacency import face_adjacency
from .atlas import chart_plane_area, estimate_density, pack_charts
from .clustering import cut_long_charts, make_injective, signed_axis_clusters
from .errors import SeamlessAOError
from .mesh import TriangleMesh, require_faces
from .raster import rasterise

#: Target duration of one :meth:`AOJob.step` (seconds).
STEP_SECONDS = 0.3
#: Distant parts of one chart must stay this many texels apart (bilinear reads 1).
SEPARATION_TEXELS = 3.0
#: With a texel density given, charts longer than this many texels are cut.
LONGEST_CHART_TEXELS = 1024


@dataclass
class Layout:
    """Everything about where AO is stored, before any ray is cast.

    Several meshes (objects baked together into one shared image) are one
    combined mesh whose parts never share an edge or a chart:
    ``part_of_triangle`` says which input mesh each triangle came from.
    """

    mesh: object
    topology: object
    charts: object
    atlas: object
    texels: object
    part_of_triangle: np.ndarray = None
    timings: dict = field(default_factory=dict)

    def part_of_texel(self, selection=slice(None)):
        """(k,) int: input mesh of each texel."""
        return self.part_of_triangle[self.atlas.member_triangle[self.texels.member[selection]]]


def build_layout(meshes, compare_angle=60.0, image_size=1024, density=None, padding=4):
    """Charts, atlas and texels for one or several meshes (one shared image).

    Parameters
    ----------
    meshes : TriangleMesh or list of TriangleMesh
    compare_angle : float, degrees
    image_size : int or None
        Square image size (used when ``density`` is None).
    density : float or None
        Texels per object unit; overrides ``image_size``.
    padding : int, texels

    Returns
    -------
    Layout
    """
    meshes = [meshes] if isinstance(meshes, TriangleMesh) else list(meshes)
    for mesh in meshes:
        require_faces(mesh)
    timings = {}
    start = time.perf_counter()
    topologies = [face_adjacency(mesh) for mesh in meshes]
    charts = [signed_axis_clusters(mesh, topology, compare_angle) for mesh, topology in zip(meshes, topologies)]
    timings["charts"] = time.perf_counter() - start

    start = time.perf_counter()
    area = sum(chart_plane_area(mesh, c) for mesh, c in zip(meshes, charts))
    expected = density if density is not None else estimate_density(area, image_size)
    # One injectivity pass with a margin: it splits folds (what cluster_faces
    # does) and also keeps distant parts of a chart a few texels apart, so
    # filtering at a chart's edge never mixes in AO from another surface.
    charts = [make_injective(mesh, topology, c, margin=SEPARATION_TEXELS / expected)
              for mesh, topology, c in zip(meshes, topologies, charts)]
    # no chart longer than a quarter of the image at the expected density (charts are never rotated)
    longest = (image_size / 4 if density is None else LONGEST_CHART_TEXELS) / expected
    charts = [cut_long_charts(mesh, c, longest) for mesh, c in zip(meshes, charts)]
    timings["injectivity"] = time.perf_counter() - start
    start = time.perf_counter()
    mesh, offsets = TriangleMesh.concatenate(meshes) if len(meshes) > 1 else (meshes[0], np.array([0, len(meshes[0].triangles)]))
    topology = merge_topologies(meshes, topologies) if len(meshes) > 1 else topologies[0]
    charts = merge_charts(charts) if len(meshes) > 1 else charts[0]
    atlas = pack_charts(mesh, topology, charts, padding=padding,
                        image_size=None if density is not None else image_size, density=density)
    charts = atlas.charts
    timings["pack"] = time.perf_counter() - start

    start = time.perf_counter()
    texels = rasterise(atlas, mesh, padding=atlas.padding)
    timings["rasterise"] = time.perf_counter() - start
    if not len(texels):
        raise SeamlessAOError("No texel landed on the mesh; raise the image size or texel density")
    part = np.repeat(np.arange(len(meshes)), np.diff(offsets))
    return Layout(mesh, topology, charts, atlas, texels, part, timings)


def merge_topologies(meshes, topologies):
    """One :class:`~.adjacency.Topology` for :meth:`TriangleMesh.concatenate`'d meshes."""
    from .adjacency import Topology
    from .mesh import MeshReport

    welded_offsets = np.cumsum([0] + [int(t.welded.max()) + 1 if len(t.welded) else 0 for t in topologies])
    face_offsets = np.cumsum([0] + [m.face_count for m in meshes])
    report = MeshReport(**{
        name: sum(getattr(t.report, name) for t in topologies) for name in MeshReport.__dataclass_fields__})
    return Topology(
        welded=np.concatenate([t.welded + o for t, o in zip(topologies, welded_offsets)]),
        welded_triangles=np.concatenate([t.welded_triangles + o for t, o in zip(topologies, welded_offsets)]),
        face_edges=np.concatenate([t.face_edges + o for t, o in zip(topologies, face_offsets)]),
        report=report,
    )


def merge_charts(parts):
    """One :class:`~.clustering.Charts` for several meshes' charts (ids offset, never shared)."""
    from .clustering import Charts

    offsets = np.cumsum([0] + [c.count for c in parts])
    return Charts(
        chart_of_face=np.concatenate([np.where(c.chart_of_face >= 0, c.chart_of_face + o, -1)
                                      for c, o in zip(parts, offsets)]),
        chart_axis=np.concatenate([c.chart_axis for c in parts]),
        dominant_axis=np.concatenate([c.dominant_axis for c in parts]),
        splits=sum(c.splits for c in parts),
    )


def estimated_bytes(texel_count, image_pixels):
    """Peak memory estimate of a bake, in bytes (dense maps + per-texel arrays + batches)."""
    return int(image_pixels * 10 + texel_count * 40 + 512 * 2**20)


def layer_lookup(atlas, mesh, triangle, bary):
    """UV of surface points in the three layers.

    Parameters
    ----------
    triangle : (k,) int
    bary : (k, 3) float

    Returns
    -------
    (k, 3, 2) float64: UV per layer (X, Y, Z).
    """
    uv = atlas.layer_uv()[triangle]                     # (k, 3 layers, 3 corners, 2)
    return np.einsum("kc,klcd->kld", bary, uv)


class AOJob:
    """AO of every texel of a layout, computed one batch per :meth:`step`.

    Two passes: the pilot rays for every texel, then the remaining rays for
    the texels that cannot stop early (see :mod:`.ao`: a texel stops when its
    pilot rays and all its atlas neighbours' agree).  The operator calls
    :meth:`step` once per timer event (each batch is about ``batch_rays``
    rays, a fraction of a second), so it can draw progress and react to ESC
    between batches; :meth:`run` does it all at once.

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
        from .ao import occlusion_sums
        from .raster import texel_geometry

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
        from .ao import pilot_agreement

        self.pilot = False
        self.position = 0
        texels = self.layout.texels
        pilot_count = len(self.rays)
        if not len(self.remaining):
            self.queue = self.queue[:0]
            return
        code = pilot_agreement(self.sums[self.queue], self.params) if self.params.adaptive else np.zeros(
            len(self.queue), dtype=np.int8)
        decided = code > 0
        if decided.any():
            decided &= neighbours_agree(texels, self.queue, code)
        self.sums[self.queue[decided]] *= self.params.rays / pilot_count
        self.queue = self.queue[~decided]
        self.rays = self.remaining
        self.work_expected = self.work_done + len(self.queue) * len(self.rays)

    def run(self, should_cancel=None, progress=None):
        """All batches; ``should_cancel()`` is polled between batches (raises :class:`BakeCancelled`)."""
        from .errors import BakeCancelled

        while not self.finished:
            if should_cancel is not None and should_cancel():
                raise BakeCancelled()
            fraction = self.step()
            if progress is not None:
                progress(fraction)
        return self.ao


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
