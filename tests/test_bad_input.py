"""Issue 7: bad input gets one clear sentence and changes nothing; failures and cancels roll back."""

import bpy
import numpy as np
import pytest

from blender_checks import image_array, material_snapshot, mesh_snapshot
from blender_scenes import add_object, suzanne
from conftest import seamless_ao
from seamless_ao.core.errors import BakeCancelled, SeamlessAOError
from seamless_ao.operators import api
from seamless_ao.shaders.material import enable_nodes

FAST = dict(image_size=256, rays=8)


def blend_state():
    """Everything a bake may touch, comparable with ==."""
    meshes = {m.name: mesh_snapshot(m) for m in bpy.data.meshes}
    materials = {m.name: material_snapshot(m) for m in bpy.data.materials}
    images = {}
    for image in bpy.data.images:
        pixels = image_array(image).tobytes() if image.has_data or image.packed_file else b""
        images[image.name] = (tuple(image.size), pixels)
    groups = sorted(bpy.data.node_groups.keys())
    objects = {o.name: (tuple(s.material.name if s.material else "" for s in o.material_slots), dict(o.items()))
               for o in bpy.data.objects}
    return meshes, materials, images, groups, objects, len(bpy.data.scenes)


@pytest.fixture
def monkey(addon, fresh_scene):
    ob = suzanne(1)
    material = bpy.data.materials.new("Skin")
    enable_nodes(material)
    ob.data.materials.append(material)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    return ob


def expect_refusal(objects, match, **settings):
    before = blend_state()
    with pytest.raises(SeamlessAOError, match=match):
        seamless_ao.bake(objects, **settings)
    assert blend_state() == before


def test_no_objects(monkey):
    expect_refusal([], "Select a mesh object")


def test_operator_poll_explains_itself(monkey):
    monkey.select_set(False)
    bpy.context.view_layer.objects.active = None
    assert not bpy.ops.object.seamless_ao_bake.poll()
    assert api.selection_problem(bpy.context) == "Select a mesh object to bake"


def test_non_mesh_object(monkey):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    bpy.context.scene.collection.objects.link(camera)
    expect_refusal([camera], "'Camera' is not a mesh")


def test_empty_mesh_and_loose_edges(monkey):
    empty = add_object("Empty Mesh", bpy.data.meshes.new("Empty Mesh"))
    expect_refusal([empty], "has no faces")
    edges = bpy.data.meshes.new("Edges")
    edges.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [(0, 1), (1, 2)], [])
    expect_refusal([add_object("Edges", edges)], "has no faces to bake \\(only vertices or loose edges\\)")


def test_edit_mode(monkey):
    before = blend_state()
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        with pytest.raises(SeamlessAOError, match="is in Edit Mode; press Tab to leave it"):
            seamless_ao.bake([monkey])
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
    assert blend_state() == before


def test_too_many_uv_maps(monkey):
    while len(monkey.data.uv_layers) < 6:
        monkey.data.uv_layers.new()
    expect_refusal([monkey], "already has 6 UV maps; Blender allows 8")


def test_memory_budget(monkey):
    expect_refusal([monkey], "memory budget", image_size=8192, memory_budget_mb=256)


def test_max_distance_zero_or_negative(monkey):
    for value in (0.0, -1.0):
        expect_refusal([monkey], "max_distance must be", auto_distance=False, max_distance=value)


def test_unknown_setting(monkey):
    expect_refusal([monkey], "Unknown setting rayz", rayz=3)


def test_linked_library_data(monkey, tmp_path):
    library = tmp_path / "library.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(library))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    with bpy.data.libraries.load(str(library), link=True) as (source, target):
        target.objects = ["Suzanne"]
    linked = target.objects[0]
    bpy.context.scene.collection.objects.link(linked)
    expect_refusal([linked], "is linked from a library")


def test_shared_mesh_objects(monkey):
    twin = bpy.data.objects.new("Twin", monkey.data)
    bpy.context.scene.collection.objects.link(twin)
    expect_refusal([monkey, twin], "share one mesh")


def test_topology_changing_modifier_is_refused(monkey):
    monkey.modifiers.new("Subdivision", "SUBSURF")
    expect_refusal([monkey], "Subdivision change the mesh's topology")


def test_deforming_modifier_bakes_the_evaluated_shape(monkey):
    modifier = monkey.modifiers.new("Displace", "DISPLACE")
    modifier.strength = 0.2
    report = seamless_ao.bake([monkey], **FAST)
    assert report.texels > 0 and "AO_X" in monkey.data.uv_layers


@pytest.mark.parametrize("step", ["image", "uv_maps", "materials"])
def test_injected_failure_changes_nothing(monkey, step):
    before = blend_state()
    api.inject_failure = step
    try:
        with pytest.raises(RuntimeError, match="injected failure"):
            seamless_ao.bake([monkey], **FAST)
    finally:
        api.inject_failure = None
    assert blend_state() == before


@pytest.mark.parametrize("step", ["image", "uv_maps", "materials"])
def test_failed_rebake_restores_the_previous_bake(monkey, step):
    seamless_ao.bake([monkey], **FAST)
    before = blend_state()
    api.inject_failure = step
    try:
        with pytest.raises(RuntimeError):
            seamless_ao.bake([monkey], image_size=512, rays=4, seed=9)
    finally:
        api.inject_failure = None
    assert blend_state() == before


def test_cancel_midway_changes_nothing(monkey):
    before = blend_state()
    calls = []

    def cancel_after_a_few_steps():
        calls.append(1)
        return len(calls) > 4

    with pytest.raises(BakeCancelled):
        seamless_ao.bake([monkey], should_cancel=cancel_after_a_few_steps, image_size=512, rays=64)
    assert len(calls) > 4
    assert blend_state() == before


def test_zero_scale_is_refused(monkey):
    monkey.scale = (1.0, 0.0, 1.0)
    expect_refusal([monkey], "'Suzanne' is scaled to zero along an axis")


def test_zero_scale_of_a_parent_is_refused(monkey):
    parent = bpy.data.objects.new("Flat parent", None)
    bpy.context.scene.collection.objects.link(parent)
    parent.scale = (0.0, 1.0, 1.0)
    monkey.parent = parent
    bpy.context.view_layer.update()
    expect_refusal([monkey], "'Suzanne' is scaled to zero along an axis")
