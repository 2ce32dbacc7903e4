"""A whole bake on arrays: meshes and a ray caster in, the AO image, the layout and the report's numbers out.

    pipeline = BakePipeline(meshes, matrices, settings, make_caster)
    for fraction, message in pipeline.steps():      # one step per call: a modal operator polls between them
        ...
    result = pipeline.result                         # BakeResult

    result = bake_arrays([mesh], settings=BakeSettings(rays=32))   # all steps at once, mathutils' BVH

The steps: memory estimate, layout (charts, atlas, texels: :mod:`.layout`),
each mesh's rays (:mod:`.rays.ray_setup`), the rays themselves in batches
(:class:`.rays.job.AOJob`), the noise estimate, the denoiser and the finished
image.  The Blender side (``operators/adapters/session.py``) only reads the
meshes, makes casters, and writes what :class:`BakeResult` holds.
"""

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from .atlas.viewport_uv import surface_uv
from .budget import check_budget, planned_size
from .freed_memory import freed_memory_held, give_back_freed_memory
from .image.denoise import denoise
from .image.fill import texel_image
from .layout import Layout, build_layout
from .rays.ao import noise_estimate
from .rays.job import AOJob
from .rays.ray_setup import BVHCaster, ray_part
from .rays.targets import TexelTargets
from .settings import BakeSettings


@dataclass
class BakeResult:
    """What a bake computed, before anything is written."""

    layout: Layout
    image: np.ndarray              # (height, width) float32, the AO image in [0, 1]
    texel_ao: np.ndarray           # (n,) float32, each texel's AO (denoised when asked)
    computed: np.ndarray           # (n,) bool, texels that got rays of their own
    buried: np.ndarray             # (n,) bool, computed texels inside another piece (never seen)
    ray_count: np.ndarray          # (n,) int, rays each texel was meant to get
    texels: int                    # texels that got rays
    rays: int                      # rays cast
    noise: float                   # ray noise before denoising, of the texels that got all their rays
    caster: str                    # the caster's name
    timings: dict = field(default_factory=dict)     # seconds of each stage
    warnings: list = field(default_factory=list)    # sentences for the user (the atlas')
    shown_uv: dict = field(default_factory=dict)    # part: (3, l, 2) float32, UVs of the surface it shows

    @property
    def layer_uv(self):
        """(t, 3 layers, 3 corners, 2) float64: every triangle's UVs in AO_X, AO_Y and AO_Z."""
        return self.layout.atlas.layer_uv()

    def part_axis_uv(self, part, dtype=np.float32):
        """The UVs of input mesh ``part``'s triangles in AO_X, AO_Y and AO_Z: three (k, 3 corners, 2), each worked
        out when read (:class:`LayerByLayer`), as ``dtype``: float32 (what a UV map holds) unless asked."""
        triangles = self.part_triangles(part)
        return LayerByLayer(lambda axis: self.layout.atlas.axis_uv(axis, triangles, dtype))

    def part_layer_drop(self, part):
        """(k, 3) int8: for input mesh ``part``'s triangles, the coordinate each one's chart in AO_X, AO_Y and
        AO_Z projects away (:meth:`.atlas.chart_atlas.Atlas.layer_drop`)."""
        triangles = self.part_triangles(part)
        return np.stack([self.layout.atlas.layer_drop(axis, triangles) for axis in range(3)], axis=1)

    def part_shown_uv(self, part):
        """(3 layers, l, 2) float32: UVs for the corners of the surface input mesh ``part`` shows in the
        viewport (:func:`.atlas.viewport_uv.surface_uv`), or None where none was given."""
        return self.shown_uv.get(part)

    def part_triangles(self, part):
        """Slice of the combined mesh's triangles that came from input mesh ``part``."""
        counts = np.bincount(self.layout.part_of_triangle, minlength=part + 1)
        start = int(counts[:part].sum())
        return slice(start, start + int(counts[part]))


class LayerByLayer(Sequence):
    """The three UV layers AO_X, AO_Y and AO_Z, each made by ``make(axis)`` when read and not kept: a writer
    that reads them one at a time holds one layer (48 bytes a triangle in float64), not all three (144 MB
    at a million triangles, bench_million's peak while the UV maps were written)."""

    def __init__(self, make):
        self._make = make

    def __len__(self):
        return 3

    def __getitem__(self, axis):
        if not 0 <= axis < 3:
            raise IndexError(axis)
        return self._make(axis)


class BakePipeline:
    """One bake on arrays, step by step (:meth:`steps`); :attr:`result` is set after the last step.

    Parameters
    ----------
    meshes : list of TriangleMesh, in object space
    matrices : list of (4, 4) float, each mesh's world matrix (what its rays see)
    settings : BakeSettings
    make_caster : callable ``(positions, triangles, sealed) -> RayCaster`` (:class:`.rays.ray_setup.BVHCaster`, or the
        Blender side's Geometry Nodes caster)
    occluders : list (one per mesh) of lists of ``(world positions (v, 3), triangles (t, 3))``, optional
        The scene geometry within each mesh's ray reach (:func:`.rays.ray_setup.world_reach`), read once by the caller;
        used when the settings ask for scene occluders.
    free_casters : callable ``(casters) -> None``, optional
        Frees several casters at once (the Blender side removes all their datablocks in one call); by
        default each caster's ``free()``.
    shown : list (one per mesh) of None or ``(positions (v, 3), corner_vert (l,), loop_start (f,))``, optional
        Another surface the mesh shows (the viewport's, at other Subdivision levels), in its object space:
        the result then holds UVs for its corners (:meth:`BakeResult.part_shown_uv`).
    caster_sources : list (one per mesh) of None or what the caller read the mesh from, optional: handed to
        ``make_caster`` as ``source=`` where a caster's occluders are that mesh alone
        (:func:`.rays.ray_setup.ray_part`; the Blender side's copy of the evaluated mesh)
    """

    def __init__(self, meshes, matrices, settings, make_caster, occluders=None, free_casters=None, shown=None,
                 caster_sources=None):
        self.meshes = list(meshes)
        self.triangle_count = sum(len(mesh.triangles) for mesh in self.meshes)      # all meshes together
        self.matrices = [np.asarray(m, dtype=np.float64) for m in matrices]
        self.settings = settings.resolved()             # the Quality preset's image size and rays filled in
        self.make_caster = make_caster
        self.occluders = occluders
        self.free_casters = free_casters or _free_each
        self.shown = list(shown) if shown is not None else [None] * len(self.meshes)
        self.caster_sources = list(caster_sources) if caster_sources is not None else [None] * len(self.meshes)
        self.parts = []
        self.result = None

    def check_memory(self, layout=None):
        """Refuse (:class:`.errors.SeamlessAOError`) a bake estimated to need more than the memory budget:
        from the surface area before the layout, from the layout's texels and image after it."""
        if layout is None:
            pixels, texels = planned_size(self.settings, sum(float(m.triangle_area.sum()) for m in self.meshes))
        else:
            pixels, texels = layout.atlas.width * layout.atlas.height, len(layout.texels)
        check_budget(self.settings, self.triangle_count, pixels, texels)

    def steps(self):
        """Yield ``(fraction, message)`` after each step; the casters are freed however it ends, and the memory
        one step frees is held for the next (:func:`.freed_memory.freed_memory_held`)."""
        with freed_memory_held(self.triangle_count):
            yield from self._steps()

    def _steps(self):
        settings = self.settings
        try:
            self.check_memory()
            yield 0.05, "Building charts and atlas"
            layout = build_layout(
                self.meshes, settings.compare_angle,
                image_size=settings.image_size if settings.size_mode == "IMAGE_SIZE" else None,
                density=settings.texel_density if settings.size_mode == "DENSITY" else None,
                padding=settings.padding, rays=settings.rays)
            self.check_memory(layout)
            yield 0.15, "Preparing rays"
            for index, (mesh, matrix) in enumerate(zip(self.meshes, self.matrices)):
                near = self.occluders[index] if self.occluders is not None and settings.use_scene_occluders else None
                self.parts.append(ray_part(mesh, matrix, settings, self.make_caster, near,
                                           source=self.caster_sources[index]))
            targets = TexelTargets(layout)
            job = AOJob(targets, self.parts, weighted=settings.weighted_rays)
            # Where Cycles bakes the bulk, its scene and the pilot's BVH come next, in blocks of their own: the
            # layout's freed temporaries go back first.  A bake the node casts alone keeps them (no peak to keep
            # down there, and the pages would fault back in: 0.3 to 0.6 s at a million triangles).
            if job.whole_parts.any():
                give_back_freed_memory(self.triangle_count)
            while not job.finished:
                fraction = job.step()
                yield 0.15 + 0.8 * fraction, "Casting rays: {:.0%}".format(fraction)
            caster_warnings = list(dict.fromkeys(warning for part in self.parts for warning in part.caster.warnings))
            self.free()
            ao, sampled, timings = job.ao, job.noise_texels(), dict(layout.timings)
            noise = noise_estimate(ao[sampled], job.ray_count[sampled], layout.texels.next_in_row(
                layout.atlas.member_chart[layout.texels.member], sampled))
            if settings.denoise:
                yield 0.95, "Denoising"
                start = time.perf_counter()
                ao = denoise(layout.texels, layout.atlas, layout.mesh, ao, job.seen, job.ray_count,
                             geometry=targets.geometry)
                timings["denoise"] = time.perf_counter() - start
            self.result = BakeResult(
                layout=layout, image=texel_image(layout.texels, ao, job.computed), texel_ao=ao,
                computed=job.computed, buried=job.buried, ray_count=job.ray_count, texels=job.total,
                rays=job.rays_cast, noise=noise, caster=job.caster_name(),
                timings=dict(timings, rays=job.seconds),
                warnings=list(layout.atlas.warnings) + caster_warnings)
            if any(surface is not None for surface in self.shown):
                yield 0.97, "UV maps for the viewport's surface"
                start = time.perf_counter()
                for part, surface in enumerate(self.shown):
                    if surface is not None:
                        self.result.shown_uv[part] = self.shown_surface_uv(part, surface)
                self.result.timings["viewport"] = time.perf_counter() - start
        finally:
            self.free()

    def shown_surface_uv(self, part, surface):
        """UVs for ``surface`` (``(positions, corner_vert, loop_start)``) from mesh ``part``'s charts."""
        mesh, atlas = self.meshes[part], self.result.layout.atlas
        return surface_uv((mesh.positions, mesh.triangles), np.stack(self.result.part_axis_uv(part, np.float64)),
                          self.result.part_layer_drop(part), surface, (atlas.width, atlas.height))

    def free(self):
        """Free every caster made so far (safe to call twice)."""
        self.free_casters([part.caster for part in self.parts])
        self.parts = []

    def run(self):
        """All steps at once; returns the :class:`BakeResult`."""
        for _ in self.steps():
            pass
        return self.result


def _free_each(casters):
    for caster in casters:
        caster.free()


def bake_arrays(meshes, matrices=None, settings=None, make_caster=BVHCaster, **overrides):
    """Bake meshes given as arrays, all steps at once, with mathutils' BVH unless told otherwise.

    Parameters
    ----------
    meshes : TriangleMesh or list of TriangleMesh
    matrices : list of (4, 4) float, optional, world matrices (default: identity)
    settings : BakeSettings, optional (default: the built-in defaults)
    make_caster : callable, optional, ``(positions, triangles, sealed) -> RayCaster``
    **overrides : any :class:`.settings.BakeSettings` field, e.g. ``rays=32``

    Returns
    -------
    BakeResult
    """
    meshes = [meshes] if not isinstance(meshes, (list, tuple)) else list(meshes)
    matrices = [np.eye(4)] * len(meshes) if matrices is None else matrices
    settings = (settings or BakeSettings()).replace(**overrides) if overrides else (settings or BakeSettings())
    return BakePipeline(meshes, matrices, settings, make_caster).run()
