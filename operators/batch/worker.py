"""One asset of a batch, in a worker process of its own: load it, bake it, write the result.

``operators/batch/runner.py`` starts one worker per asset (a background Blender, or
Python with the bpy module) and hands it a job file; the worker writes one
:class:`~..core.batch.AssetRecord` as JSON and exits.  Nothing from the asset
runs: .blend files are opened with auto-run scripts off.

- ``.blend`` in: the meshes are baked as the ``bake`` command does and the
  file is saved as the output.
- anything else (``.glb``, ``.gltf``, ``.obj``, ``.fbx``, ``.ply``, ``.stl``)
  in: imported, baked, the AO resampled onto each object's own UV map (a
  new one, ``AO_UV``, when it has none or its own cannot hold the AO: see
  ``batch``'s ``uv_policy``) and wired into
  its materials as the glTF occlusion texture; written as ``.glb``.
"""

import json
import math
import os
import sys
import time
import traceback

import addon_utils
import bpy
import numpy as np

from ...core.errors import SeamlessAOError
from ...core.keys import AO_LAYERS, AO_UV, COLOR_ATTRIBUTE, GLTF_NODES
from ...core.other_processes.batch_plan import AssetRecord, partial_output
from ...core.settings import RESAMPLE_FIELDS, BakeSettings, GltfSettings, gltf_fields
from ...shaders import material as material_nodes
from ..adapters.exports import own_uv_map, render_active_uv, resample, to_color_attribute, uv_map_fitness
from ..adapters.mesh_data import evaluated_mesh, render_evaluation
from ..adapters.session import bake


IMPORTERS = {
    ".glb": ("io_scene_gltf2", lambda path: bpy.ops.import_scene.gltf(filepath=path)),
    ".gltf": ("io_scene_gltf2", lambda path: bpy.ops.import_scene.gltf(filepath=path)),
    ".fbx": ("io_scene_fbx", lambda path: bpy.ops.import_scene.fbx(filepath=path)),
    ".obj": (None, lambda path: bpy.ops.wm.obj_import(filepath=path)),
    ".ply": (None, lambda path: bpy.ops.wm.ply_import(filepath=path)),
    ".stl": (None, lambda path: bpy.ops.wm.stl_import(filepath=path)),
}


def load_asset(path):
    """Open a .blend (scripts off) or import any other asset into an empty scene."""
    suffix = os.path.splitext(path)[1].lower()
    name = os.path.basename(path)
    try:
        if suffix == ".blend":
            bpy.ops.wm.open_mainfile(filepath=path, load_ui=False, use_scripts=False)
            return
        bpy.ops.wm.read_factory_settings(use_empty=True)
        addon, importer = IMPORTERS[suffix]
        if addon is not None:
            addon_utils.enable(addon, default_set=False)
        importer(path)
    except Exception as error:        # the importers raise RuntimeError, or their own errors on bad data
        reason = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise SeamlessAOError("could not read {}: {}".format(name, reason.replace("Error: ", ""))) from None


def bake_targets(source_name):
    """The scene's visible mesh objects with faces (all visible meshes if none has faces: the bake's
    own check then says what is wrong with them)."""
    view_layer = bpy.context.view_layer
    meshes = [ob for ob in view_layer.objects if ob.type == "MESH" and ob.visible_get(view_layer=view_layer)]
    if not meshes:
        raise SeamlessAOError("{} has no visible mesh object to bake".format(source_name))
    with_faces = [ob for ob in meshes if len(ob.data.polygons) or any(m.show_render for m in ob.modifiers)]
    return with_faces or meshes


def make_single_user(objects):
    """Give every object a mesh of its own (instances share UV maps, but not AO); returns how many."""
    seen, copied = set(), 0
    for ob in objects:
        if ob.data in seen:
            ob.data = ob.data.copy()
            copied += 1
        seen.add(ob.data)
    return copied


def triangle_count(objects):
    """Triangles of the objects as they render (modifier stacks evaluated)."""
    total = 0
    with render_evaluation(objects):
        depsgraph = bpy.context.evaluated_depsgraph_get()
        for ob in objects:
            with evaluated_mesh(ob, depsgraph) as mesh:
                corners = np.empty(len(mesh.polygons), dtype=np.int64)
                mesh.polygons.foreach_get("loop_total", corners)
                total += int(np.maximum(corners - 2, 0).sum())
    return total


def bake_all(objects, settings, per_object):
    """Bake ``objects`` together (one image) or one image each; fill the record's numbers."""
    reports = [bake(group, settings=settings) for group in ([ob] for ob in objects)] if per_object else [
        bake(objects, settings=settings)]
    seconds = {}
    for report in reports:
        for stage, value in report.timings.items():
            seconds[stage] = seconds.get(stage, 0.0) + value
    return dict(
        texels=sum(r.texels for r in reports), rays=float(sum(r.rays for r in reports)),
        noise=max(r.noise for r in reports), seconds=seconds,
        warnings=[w for r in reports for w in r.warnings] + sorted({p for r in reports for p in r.mesh_problems}))


def unwrap(ob, padding, size):
    """A new UV map ``AO_UV`` made by Smart UV Project, islands ``padding`` texels apart at ``size``."""
    mesh = ob.data
    layer = mesh.uv_layers.get(AO_UV) or mesh.uv_layers.new(name=AO_UV)
    mesh.uv_layers.active = layer
    view_layer = bpy.context.view_layer
    for other in view_layer.objects:
        other.select_set(False)
    view_layer.objects.active = ob
    ob.select_set(True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(angle_limit=math.radians(66.0), island_margin=max(2, padding) / size)
    bpy.ops.object.mode_set(mode="OBJECT")
    return AO_UV


def own_materials(objects):
    """Every slot of every object filled, and no material shared between objects (the first keeps it,
    the others get copies): the glTF occlusion texture belongs to a material, and each object has its
    own AO image."""
    taken = set()
    for ob in objects:
        if not ob.material_slots:
            ob.data.materials.append(None)
        copies = {}
        for slot in ob.material_slots:
            if slot.material is None:
                slot.material = material_nodes.new_material(ob.name + "_AO")
            elif slot.material in taken:
                original = slot.material
                if original not in copies:
                    copies[original] = original.copy()
                slot.material = copies[original]
        taken.update(slot.material for slot in ob.material_slots)


def ao_uv_map(ob, policy, padding, size):
    """The UV map ``ob``'s AO rides on under ``policy`` (``auto``, ``own``, ``new``: see ``batch``), and the
    warnings to record."""
    own = [uv for uv in ob.data.uv_layers if uv.name not in AO_LAYERS and uv.name != AO_UV]
    if not own or policy == "new":
        return unwrap(ob, padding, size), []
    target = own_uv_map(ob)
    fitness = uv_map_fitness(ob, target)
    if fitness.can_hold_ao:
        return target, []
    reason = "; ".join(fitness.problems())
    if policy == "own":
        return target, ["'{}': its UV map '{}' cannot hold the AO ({}), and it carries it as asked (--uv-policy "
                        "own): the AO of one place shows in another".format(ob.name, target, reason)]
    return unwrap(ob, padding, size), ["'{}': its UV map '{}' cannot hold the AO ({}): the AO rides on a new UV "
                                       "map {} (glTF TEXCOORD_1)".format(ob.name, target, reason, AO_UV)]


def share_orm(ob, target):
    """With ORM packing, a material whose Roughness or Metallic comes from a texture on the AO's UV map reads
    both from the ORM image's G and B instead (which hold that texture's texels there), so the glTF carries
    one image as its occlusion and metallic-roughness texture.  Only the batch's loaded copy changes."""
    default_uv_map = render_active_uv(ob)
    for material in {slot.material for slot in ob.material_slots if slot.material is not None}:
        split = material.node_tree.nodes.get(GLTF_NODES[2])
        principled = material_nodes.principled_bsdf(material)
        textures = [texture for _, texture in material_nodes.principled_values(material, default_uv_map).values()
                    if texture]
        if split is None or principled is None or not any(uv_map == target for _, _, uv_map in textures):
            continue
        links = material.node_tree.links
        links.new(split.outputs["Green"], principled.inputs["Roughness"])
        links.new(split.outputs["Blue"], principled.inputs["Metallic"])


def export_glb(objects, output, job):
    """Resample the AO onto each object's UV map, wire it as occlusion and write ``output`` (.glb); returns
    the warnings about the UV maps."""
    gltf = GltfSettings.from_kwargs(**{f.name: job[f.name] for f in gltf_fields()})
    texture = gltf.resample_settings().replace(gltf_occlusion=True, unfit_uv_map=True)
    resampled = {name: getattr(texture, name) for name in RESAMPLE_FIELDS if name != "uv_map"}
    colours = gltf.color_attribute != "NONE"
    own_materials(objects)
    warnings = []
    for ob in objects:
        target, said = ao_uv_map(ob, gltf.uv_policy, texture.padding, texture.size)
        warnings += said
        resample([ob], uv_map=target, **resampled)
        if texture.packing == "ORM":
            share_orm(ob, target)
    if colours:
        to_color_attribute(objects, gltf.color_attribute)
    for ob in objects:
        for name in AO_LAYERS:           # the bake's own maps are not part of the shipped asset
            layer = ob.data.uv_layers.get(name)
            if layer is not None:
                ob.data.uv_layers.remove(layer)
        if colours:
            ob.data.color_attributes.active_color_name = COLOR_ATTRIBUTE
    addon_utils.enable("io_scene_gltf2", default_set=False)
    options = dict(filepath=output, export_format="GLB", use_selection=False, export_texcoords=True,
                   export_normals=True, export_materials="EXPORT")
    known = bpy.ops.export_scene.gltf.get_rna_type().properties.keys()
    if colours:
        options.update({"export_vertex_color": "ACTIVE"} if "export_vertex_color" in known else
                       {"export_colors": True})
    bpy.ops.export_scene.gltf(**options)
    return warnings


def write_output(objects, job, from_blend):
    """The .blend or .glb, written under a temporary name and then renamed: a crash never leaves a
    half-written output that a re-run would take as done.  Returns the export's warnings."""
    output = job["output"]
    partial = partial_output(output, os.getpid())
    warnings = []
    try:
        if from_blend:
            bpy.ops.wm.save_as_mainfile(filepath=partial, copy=True)
        else:
            warnings = export_glb(objects, partial, job)
        os.replace(partial, output)
    finally:
        if os.path.exists(partial):
            os.remove(partial)
    return warnings


def run_job(job):
    """Bake one asset as ``job`` says; returns its :class:`AssetRecord` (``error`` set if it failed)."""
    record = AssetRecord(input=job["input"], output=job["output"])
    started = time.perf_counter()
    name = os.path.basename(job["input"])
    try:
        load_asset(job["input"])
        record.seconds["load"] = time.perf_counter() - started
        from_blend = job["input"].lower().endswith(".blend")
        settings = BakeSettings.from_kwargs(**job["settings"])
        if not from_blend:
            settings = settings.replace(hook_materials=False, save_image="NONE")   # glTF keeps its Base Color
        objects = bake_targets(name)
        # a .blend keeps its linked duplicates (each gets its AO through a modifier); a .glb exports one
        # material set per mesh, so there each object needs a mesh of its own for its own AO image
        shared = 0 if from_blend else make_single_user(objects)
        record.objects = [ob.name for ob in objects]
        record.triangles = triangle_count(objects)
        numbers = bake_all(objects, settings, job["per_object"])
        record.texels, record.rays, record.noise = numbers["texels"], numbers["rays"], numbers["noise"]
        record.seconds.update(numbers["seconds"])
        record.warnings = numbers["warnings"] + (
            ["{} object(s) shared a mesh with another and got a copy of their own".format(shared)] if shared else [])
        start = time.perf_counter()
        record.warnings += write_output(objects, job, from_blend)
        record.seconds["export"] = time.perf_counter() - start
        record.status = "baked"
    except SeamlessAOError as error:
        record.error = str(error)
    except Exception as error:          # a worker reports every failure and lets the batch go on
        traceback.print_exc()
        record.error = "unexpected {}: {}".format(type(error).__name__, error)
    record.seconds["total"] = time.perf_counter() - started
    return record


def main(argv):
    """The worker's entry point (``launch.py worker JOB.json``): run the job in the file ``argv[0]`` and
    write its record; returns the exit code."""
    with open(argv[0], encoding="utf-8") as handle:
        job = json.load(handle)
    record = run_job(job)
    with open(job["record"], "w", encoding="utf-8") as handle:
        json.dump(record.as_dict(), handle)
    print("seamless_ao worker: {} {}".format(record.status, record.error), file=sys.stderr)
    return 0 if record.status == "baked" else 1
