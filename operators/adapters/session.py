"""One bake, from Blender objects to written results: ``bake(objects, **settings) -> BakeReport``.

The bake operator, the command line and pipeline scripts all go through
:class:`BakeSession`, which reads the meshes, hands them to core's
:class:`~...core.pipeline.BakePipeline` with a ray caster, and only then
writes into Blender data, in one transaction: if anything fails or the bake
is cancelled, every mesh, UV map, material and image is left exactly as it
was.

    import bl_ext.user_default.seamless_ao as seamless_ao
    report = seamless_ao.bake([bpy.data.objects["Suzanne"]], rays=128, image_size=2048)
    print(report.summary())
"""

import dataclasses
import hashlib
import json
import time

import bpy
import numpy as np

from ...core.atlas.viewport_uv import stands_off
from ...core.errors import BakeCancelled, SeamlessAOError
from ...core.freed_memory import freed_memory_held
from ...core.keys import IMAGE_KEY
from ...core.other_processes.handoff import outcome_numbers
from ...core.pipeline import BakePipeline
from ...core.rays.ray_setup import BVHCaster, world_reach
from ...core.settings import BakeSettings, caster_words
from ..background.client import BackgroundBake
from .casters import caster_maker, free_casters
from .checks import check_objects, check_unchanged, mesh_fingerprint
from .cycles_caster import cycles_enabled
from .mesh_data import (EvaluatedCorners, islands_as_read, occluder_copy, read_object, remove_occluder_copies,
                        render_evaluation, scene_occluders, world_boxes)
from .scene_settings import settings_from
from .writes import Transaction, corner_uv, image_file_path, save_image_file


@dataclasses.dataclass
class BakedObject:
    """One object of a bake, as read (as it renders): the object, its triangles' face corners in the
    evaluated mesh (to write UVs back), its world matrix, the evaluated corners, and where the UV maps go:
    on its mesh, or (``through_stack``: its modifiers change the topology, or its mesh is shared with
    another baked object) through a ``Seamless AO`` modifier (:mod:`.stack`)."""

    ob: bpy.types.Object
    loops: np.ndarray           # (t, 3) int64, the evaluated mesh's corner of each triangle corner
    matrix: np.ndarray          # (4, 4) float64
    corners: EvaluatedCorners
    through_stack: bool
    viewport: EvaluatedCorners = None   # the surface the viewport evaluates, where its levels give another one
    viewport_part: int = None   # that surface's mesh in the pipeline, where it is baked too (it stands off)
    viewport_loops: np.ndarray = None   # (t, 3) int64, its corner of each of its triangles' corners


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
    quality: str = ""           # the Quality and what it baked with, e.g. "Good, 256², 32 rays"

    def summary(self):
        text = "Baked {} in {:.1f} s ({}): {}x{} image '{}', {:,} texels, {:,.0f} rays, {:.0%} of the image " \
               "used".format(", ".join(self.objects), self.seconds, self.quality, self.width, self.height,
                             self.image, self.texels, self.rays, self.utilisation)
        text += ", ray noise before denoising about {:.3f}".format(self.noise)
        text += ", rays cast by {}".format(caster_words(self.caster))
        if self.mesh_problems:
            text += "; handled: " + ", ".join(self.mesh_problems)
        return text

    def headline(self):
        """One short sentence for the status bar (the details are in :meth:`summary`)."""
        what = self.objects[0] if len(self.objects) == 1 else "{} objects".format(len(self.objects))
        return "Seamless AO baked {} in {:.1f} s".format(what, self.seconds)


class BakeSession:
    """One bake, step by step.

    ``for fraction, message in session.steps(): ...`` runs it; the operator
    does one step per timer event.  :meth:`cancel` (or an exception) cleans up
    and leaves all user data as it was.  After the last step, ``report`` holds
    the :class:`BakeReport`.
    """

    def __init__(self, objects, settings, scene=None, background=False):
        self.objects = list(objects)
        self.settings = settings
        self.scene = scene or bpy.context.scene
        self.background = background
        self.pipeline = None
        self.process = None
        self.report = None
        self.occluder_copies = []           # per pipeline mesh: mesh_data.OccluderCopy, or None
        self.started = time.perf_counter()
        bpy.context.evaluated_depsgraph_get()          # transforms set by a script are evaluated before the checks
        check_objects(self.objects, self.settings)

    def steps(self):
        """Read, then core's pipeline step by step (here, or in a background process), then write; yields
        ``(fraction, message)``."""
        try:
            yield 0.0, "Reading meshes"
            meshes, self.baked, occluders = self._read_meshes()
            # what the pipeline and the writes free, the next arrays reuse (core/freed_memory.py)
            with freed_memory_held(sum(len(arrays.triangles) for arrays in meshes)):
                if self.background:
                    outcome = yield from self._steps_in_background(meshes, occluders)
                    numbers = outcome.numbers
                else:
                    # each part's occluders were read and culled to its ray reach in _read_meshes
                    triangle_meshes = [arrays.mesh() for arrays in meshes]
                    # the arrays as read are done with: their float32 corner normals alone are 36 MB a million
                    # triangles, held through the whole bake beside the mesh's own
                    meshes = None
                    self.pipeline = BakePipeline(triangle_meshes, self.matrices, self.settings,
                                                 caster_maker(self.settings), occluders, free_casters, self._shown(),
                                                 self.occluder_copies)
                    yield from self.pipeline.steps()
                    outcome = self.pipeline.result
                    numbers = outcome_numbers(outcome)
                yield 0.96, "Writing image, UV maps and materials"
                check_unchanged(self.objects, self.fingerprints)
                warnings = numbers["warnings"] + self._write(outcome)
            self.report = BakeReport(
                objects=[ob.name for ob in self.objects], image=self.image_name,
                seconds=time.perf_counter() - self.started, warnings=warnings,
                quality=self.settings.chosen(numbers["width"], numbers["height"]),
                **{name: value for name, value in numbers.items() if name != "warnings"})
            store_stats(self.scene, self.report)
            yield 1.0, "Done"
        finally:
            self.cancel()

    def _shown(self):
        """Per pipeline mesh, the viewport's surface where it is not the one baked and not baked itself (its
        UVs then come from the baked one's charts), as arrays; else None."""
        shown = [None] * len(self.matrices)
        for part, b in enumerate(self.baked):
            if b.viewport is not None and b.viewport_part is None:
                shown[part] = (b.viewport.positions, b.viewport.corner_vert, b.viewport.loop_start)
        return shown

    def _steps_in_background(self, meshes, occluders):
        """The pipeline in a process of its own (:mod:`..background.client`); returns its outcome.  Ray Caster
        Automatic is resolved here, where the user may have turned Cycles off (the process starts from factory
        settings)."""
        settings = self.settings
        if settings.ray_caster == "AUTOMATIC" and not cycles_enabled():
            settings = dataclasses.replace(settings, ray_caster=settings.caster_name(cycles_enabled=False))
        self.process = BackgroundBake(meshes, self.matrices, occluders, settings, self._shown())
        while (state := self.process.poll()) is not None:
            yield state
        return self.process.outcome()

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
        """Free the casters (the pipeline's clean-up; nothing is written before the last step), or end the
        background process and remove its files."""
        if self.pipeline is not None:
            self.pipeline.free()
        remove_occluder_copies(self.occluder_copies)         # those no caster took over
        if self.process is not None:
            self.process.close()

    # -- reading ---------------------------------------------------------------

    def _read_meshes(self):
        """The baked objects and, if asked, the scene geometry near each, all as they render; returns the
        meshes (:class:`~...core.mesh.triangle_mesh.MeshArrays`: a background bake works out the rest in its own
        process), the :class:`BakedObject` of each and each one's occluders (world geometry)."""
        meshes, baked, occluders = [], [], []
        users = {}
        for ob in self.objects:
            users[ob.data] = users.get(ob.data, 0) + 1
        # as they render: the baked objects, and every object when the scene's may occlude them
        evaluated = self.scene.objects if self.settings.use_scene_occluders else self.objects
        # the Geometry Nodes casters (Cycles' too) cast against a copy of what was read, made here, as it renders
        copying = not self.background and caster_maker(self.settings) is not BVHCaster
        with render_evaluation(evaluated):
            depsgraph = bpy.context.evaluated_depsgraph_get()
            for ob in self.objects:
                arrays, loops, corners, on_base = read_object(ob, depsgraph)
                if not len(arrays.triangles):
                    raise SeamlessAOError("'{}' has no faces to bake as it renders (its modifiers leave none)".format(
                        ob.name))
                copy = occluder_copy(ob, depsgraph, arrays) if copying else None
                self.occluder_copies.append(copy)
                # Blender joins the mesh's faces into islands on all cores: its pieces need not join the triangles
                arrays.vertex_island = islands_as_read(ob, depsgraph, arrays, copy)
                matrix = np.array(ob.matrix_world, dtype=np.float64)
                meshes.append(arrays)
                baked.append(BakedObject(ob, loops, matrix, corners, not on_base or users[ob.data] > 1))
            boxes = world_boxes(depsgraph) if self.settings.use_scene_occluders else None
            for ob, mesh, part in zip(self.objects, meshes, baked):
                occluders.append(scene_occluders(boxes, ob, *world_reach(mesh.mesh(), part.matrix, self.settings))
                                 if boxes is not None else [])
        self.matrices = [part.matrix for part in baked]
        depsgraph = bpy.context.evaluated_depsgraph_get()       # as the viewport evaluates it, levels and all
        for index, part in enumerate(baked):
            if not part.through_stack:
                continue
            shown, loops, corners, _ = read_object(part.ob, depsgraph)
            if corners.counts() == part.corners.counts():
                continue
            part.viewport = corners
            if stands_off(meshes[index].positions, meshes[index].triangles, shown.positions):
                # a Subdivision cage: its own AO, baked as one more piece of the atlas, with its own rays
                part.viewport_part, part.viewport_loops = len(meshes), loops
                meshes.append(shown)
                self.occluder_copies.append(None)
                occluders.append(occluders[index])
                self.matrices.append(part.matrix)
        self.fingerprints = [mesh_fingerprint(ob) for ob in self.objects]
        return meshes, baked, occluders

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

    def _write(self, result):
        """Image, UV maps, node group, materials: all or nothing."""
        transaction = Transaction()
        warnings = []
        image_values = result.image
        try:
            image = transaction.image(self.default_image_name(), image_values)
            self.image_name = image.name
            for part, baked in enumerate(self.baked):
                part_uv = result.part_axis_uv(part)
                if baked.through_stack:
                    viewport_uv = result.part_shown_uv(part)
                    if baked.viewport_part is not None:
                        viewport_uv = corner_uv(len(baked.viewport.corner_vert), baked.viewport_loops,
                                                result.part_axis_uv(baked.viewport_part))
                    transaction.stack_uv_maps(baked.ob, baked.corners, baked.loops, part_uv, baked.viewport,
                                              viewport_uv)
                else:
                    transaction.drop_stack(baked.ob)
                    transaction.uv_maps(baked.ob.data, baked.loops, part_uv)
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
    props.last_bake_stages = json.dumps({stage: round(seconds, 4) for stage, seconds in report.timings.items()})
    props.last_bake_texels = report.texels
    props.last_bake_rays = float(report.rays)
    props.last_bake_utilisation = report.utilisation
    props.last_bake_noise = report.noise
    props.last_bake_quality = report.quality



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
