"""Blender's own route to an AO texture: Smart UV Project + Cycles "Bake > Ambient Occlusion"."""

import time

import numpy as np

import bpy

import package  # noqa: F401  (imports the add-on as ``seamless_ao``)
from seamless_ao.operators.adapters.cycles_device import cycles_device

UV_NAME = "CyclesAO"


#: Space Smart UV Project keeps between islands, in texels of the baked image; Cycles' bake margin
#: (16 px) fills the gap from both sides.  Measured at 512²/64 against the plain reference
#: (bench_cycles_margin.py; RMSE on Suzanne subdivided twice / the interior, docs/bench/bench_meshes.md):
#: 1.5 texels (the 0.003 used before) 0.0146 / 0.0466, 2 texels 0.0097 / 0.0429, 4 texels
#: 0.0137 / 0.0551.  Less lets lookups at an island's border read its neighbour; more shrinks
#: every island.
ISLAND_MARGIN_TEXELS = 2


def smart_unwrap(ob, angle_limit=66.0, island_margin=0.003):
    """A new UV map ``CyclesAO`` made by Smart UV Project (the user's other UV maps untouched);
    ``island_margin`` is a fraction of the UV square."""
    mesh = ob.data
    layer = mesh.uv_layers.get(UV_NAME) or mesh.uv_layers.new(name=UV_NAME)
    previous = mesh.uv_layers.active
    mesh.uv_layers.active = layer
    bpy.context.view_layer.objects.active = ob
    for other in bpy.context.view_layer.objects:
        other.select_set(other is ob)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(angle_limit=angle_limit * 3.14159265 / 180.0, island_margin=island_margin)
    bpy.ops.object.mode_set(mode="OBJECT")
    if previous is not None:
        mesh.uv_layers.active = previous


def half_diagonal(ob, mesh):
    """The distance Cycles' AO is baked to: half the diagonal of ``mesh``'s box as ``ob`` stands in the world
    (rotated and scaled), Seamless AO's default maximum distance."""
    return 0.5 * float(np.linalg.norm(np.ptp(mesh.positions @ np.array(ob.matrix_world)[:3, :3].T, axis=0)))


def cycles_ao_bake(ob, size, samples, distance, margin=16):
    """Bake AO with Cycles into a new float image through ``CyclesAO`` (islands
    :data:`ISLAND_MARGIN_TEXELS` apart at this image size).

    Returns ``(image, seconds_unwrap, seconds_bake)``.
    """
    scene = bpy.context.scene
    start = time.perf_counter()
    smart_unwrap(ob, island_margin=ISLAND_MARGIN_TEXELS / size)
    unwrap = time.perf_counter() - start
    image = bpy.data.images.new("Cycles_AO_{}_{}".format(size, samples), size, size, alpha=False, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    material = ob.active_material
    if material is None:
        material = bpy.data.materials.new("Cycles bake target")
        ob.data.materials.append(material)
    if material.node_tree is None:
        material.use_nodes = True
    nodes = material.node_tree.nodes
    target = nodes.new("ShaderNodeTexImage")
    target.image = image
    nodes.active = target
    scene.render.engine = "CYCLES"
    scene.cycles.device = cycles_device()[0]             # the device Cycles' preferences name, as ours
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.light_settings.distance = distance
    scene.render.bake.margin = margin
    for other in bpy.context.view_layer.objects:
        other.select_set(other is ob)
    bpy.context.view_layer.objects.active = ob
    start = time.perf_counter()
    bpy.ops.object.bake(type="AO", uv_layer=UV_NAME, margin=margin, use_clear=True)
    bake = time.perf_counter() - start
    nodes.remove(target)
    return image, unwrap, bake
