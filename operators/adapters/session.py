"""One bake, from Blender objects to written results: ``bake(objects, **settings) -> BakeReport``.

The bake operator, the command line and pipeline scripts all go through
:class:`BakeSession`, which reads the meshes, runs the core pipeline and only
then writes into Blender data, in one transaction: if anything fails or the
bake is cancelled, every mesh, UV map, material and image is left exactly as
it was.

    import bl_ext.user_default.seamless_ao as seamless_ao
    report = seamless_ao.bake([bpy.data.objects["Suzanne"]], rays=128, image_size=2048)
    print(report.summary())
"""

import dataclasses
import hashlib
import time

import bpy
import numpy as np

from ...core.ao import noise_bound
from ...core.budget import check_budget, planned_size
from ...core.denoise import denoise
from ...core.errors import BakeCancelled
from ...core.fill import texel_image
from ...core.job import AOJob
from ...core.keys import IMAGE_KEY
from ...core.pipeline import build_layout
from ...core.settings import BakeSettings
from .casters import free_casters, ray_setup
from .checks import check_objects, check_unchanged, mesh_fingerprint
from .mesh_data import mesh_boxes, read_object
from .scene_settings import settings_from
from .writes import Transaction, image_file_path, save_image_file


@dataclasses.dataclass
class BakeReport:
    """What a bake did (also stored on the scene for the panel)."""

    objects: list
    image: str
    width: int
    height: int
    texels: int
    rays: int
    utilisation: float
    density: float
    charts: int
    seconds: float
    timings: dict
    mesh_problems: list
    warnings: list
    caster: str
    noise: float = 0.0

    def summary(self):
        text = "Baked {} in {:.1f} s: {}x{} image '{}', {:,} texels, {:,.0f} rays, {:.0%} of the image used".format(
            ", ".join(self.objects), self.seconds, self.width, self.height, self.image, self.texels, self.rays,
            self.utilisation)
        text += ", noise before denoising at most {:.3f}".format(self.noise)
        if self.mesh_problems:
            text += "; handled: " + ", ".join(self.mesh_problems)
        return text


class BakeSession:
    """One bake, step by step.

    ``for fraction, message in session.steps(): ...`` runs it; the operator
    does one step per timer event.  :meth:`cancel` (or an exception) cleans up
    and leaves all user data as it was.  After the last step, ``report`` holds
    the :class:`BakeReport`.
    """

    def __init__(self, objects, settings, scene=None, depsgraph=None):
        self.objects = list(objects)
        self.settings = settings
        self.scene = scene or bpy.context.scene
        self.depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
        self.casters = []
        self.report = None
        self.started = time.perf_counter()
        check_objects(self.objects, settings)

    # Each step is a generator stage; steps() chains them.
    def steps(self):
        try:
            yield 0.0, "Reading meshes"
            meshes, frames = self._read_meshes()
            self._check_memory(meshes)
            yield 0.05, "Building charts and atlas"
            layout = build_layout(
                meshes, self.settings.compare_angle,
                image_size=self.settings.image_size if self.settings.size_mode == "IMAGE_SIZE" else None,
                density=self.settings.texel_density if self.settings.size_mode == "DENSITY" else None,
                padding=self.settings.padding)
            self._check_memory(meshes, layout)
            yield 0.15, "Preparing rays"
            boxes = mesh_boxes(self.scene, self.depsgraph) if self.settings.use_scene_occluders else None
            parts = [self._ray_part(frame, mesh, boxes) for frame, mesh in zip(frames, meshes)]
            job = AOJob(layout, parts, weighted=self.settings.weighted_rays)
            while not job.finished:
                fraction = job.step()
                yield 0.15 + 0.8 * fraction, "Casting rays: {:.0%}".format(fraction)
            ao_seconds = job.seconds
            self._free_casters()
            ao = job.ao
            seen = job.computed & ~job.buried
            noise = noise_bound(ao[seen], job.ray_count[seen])
            if self.settings.denoise:
                yield 0.95, "Denoising"
                start = time.perf_counter()
                ao = denoise(layout.texels, layout.atlas, layout.mesh, ao, seen, job.ray_count)
                layout.timings["denoise"] = time.perf_counter() - start
            yield 0.96, "Writing image, UV maps and materials"
            check_unchanged(self.objects, self.fingerprints)
            image = texel_image(layout.texels, ao, job.computed)
            warnings = list(layout.atlas.warnings) + self._write(layout, image)
            timings = dict(layout.timings, rays=ao_seconds)
            self.report = BakeReport(
                objects=[ob.name for ob in self.objects], image=self.image_name, width=layout.atlas.width,
                height=layout.atlas.height, texels=job.total, rays=job.rays_cast,
                utilisation=layout.atlas.utilisation, density=layout.atlas.density, charts=layout.charts.count,
                seconds=time.perf_counter() - self.started, timings=timings,
                mesh_problems=layout.topology.report.problems(), warnings=warnings,
                caster=parts[0][1].name, noise=noise)
            store_stats(self.scene, self.report)
            yield 1.0, "Done"
        finally:
            self._free_casters()

    def run(self, should_cancel=None, progress=None):
        """All steps at once; returns the report (raises :class:`BakeCancelled` if asked to stop)."""
        steps = self.steps()
        try:
            for fraction, message in steps:
                if progress is not None:
                    progress(fraction, message)
                if should_cancel is not None and should_cancel() and fraction < 1.0:
                    raise BakeCancelled()
        finally:
            steps.close()
        return self.report

    def cancel(self):
        self._free_casters()

    # -- stages ---------------------------------------------------------------

    def _read_meshes(self):
        meshes, frames = [], []
        for ob in self.objects:
            triangle_mesh, loops = read_object(ob, self.depsgraph)
            meshes.append(triangle_mesh)
            frames.append((ob, loops, np.array(ob.matrix_world, dtype=np.float64)))
        self.frames = frames
        self.fingerprints = [mesh_fingerprint(ob) for ob in self.objects]
        return meshes, frames

    def _check_memory(self, meshes, layout=None):
        triangles = sum(len(m.triangles) for m in meshes)
        if layout is None:
            pixels, texels = planned_size(self.settings, sum(float(m.triangle_area.sum()) for m in meshes))
        else:
            pixels, texels = layout.atlas.width * layout.atlas.height, len(layout.texels)
        check_budget(self.settings, triangles, pixels, texels)

    def _ray_part(self, frame, mesh, boxes):
        params, caster, to_ray = ray_setup(frame[0], mesh, self.settings, self.scene, self.depsgraph, boxes=boxes)
        self.casters.append(caster)
        return params, caster, to_ray

    def _free_casters(self):
        free_casters(self.casters)
        self.casters = []

    # -- writing ---------------------------------------------------------------

    def default_image_name(self):
        """``<object>_AO``, or for several objects one name made of theirs."""
        names = sorted(ob.name for ob in self.objects)
        if len(names) == 1:
            return names[0] + "_AO"
        joined = "+".join(names)
        if len(joined) > 50:
            joined = joined[:40] + "-" + hashlib.sha1(joined.encode()).hexdigest()[:8]
        return joined + "_AO"

    def _write(self, layout, image_values):
        """Image, UV maps, node group, materials: all or nothing."""
        transaction = Transaction()
        warnings = []
        try:
            image = transaction.image(self.default_image_name(), image_values)
            self.image_name = image.name
            layer_uv = layout.atlas.layer_uv()
            offsets = np.concatenate([[0], np.cumsum(np.bincount(layout.part_of_triangle,
                                                                 minlength=len(self.objects)))])
            for part, (ob, loops, _) in enumerate(self.frames):
                part_uv = layer_uv[offsets[part]:offsets[part + 1]]
                transaction.uv_maps(ob.data, loops, part_uv)
            transaction.node_group()
            for ob in self.objects:
                warnings += transaction.materials(ob, image, self.settings.hook_materials, self.objects)
                transaction.set_property(ob, IMAGE_KEY, image.name)
            if self.settings.save_image != "NONE":
                transaction.file(image_file_path(image, self.settings.save_image),
                                 lambda path: save_image_file(path, image, image_values, self.settings.save_image))
        except BaseException:
            transaction.roll_back()
            raise
        transaction.commit()
        return warnings


def store_stats(scene, report):
    """The last bake's numbers, for the panel."""
    props = getattr(scene, "seamless_ao", None)
    if props is None:
        return
    props.last_bake_summary = report.summary()
    props.last_bake_time = report.seconds
    props.last_bake_texels = report.texels
    props.last_bake_rays = float(report.rays)
    props.last_bake_utilisation = report.utilisation
    props.last_bake_noise = report.noise



def bake(objects, settings=None, scene=None, should_cancel=None, progress=None, **overrides):
    """Bake Seamless AO for ``objects`` (one shared image if several).

    Parameters
    ----------
    objects : list of bpy.types.Object
    settings : BakeSettings, optional
        Defaults to the scene's Seamless AO settings (or the built-in defaults
        when the add-on's properties are not registered).
    scene : bpy.types.Scene, optional
    should_cancel : callable, optional
        Polled between steps; return True to stop (raises BakeCancelled).
    progress : callable ``(fraction, message)``, optional
    **overrides
        Any :class:`~..core.settings.BakeSettings` field, e.g. ``rays=128``.

    Returns
    -------
    BakeReport
    """
    scene = scene or bpy.context.scene
    if settings is None:
        props = getattr(scene, "seamless_ao", None)
        if props is not None:
            settings = settings_from(props)
        else:
            settings = BakeSettings()
    if overrides:
        settings = settings.replace(**overrides)
    session = BakeSession(objects, settings, scene=scene)
    return session.run(should_cancel, progress)
