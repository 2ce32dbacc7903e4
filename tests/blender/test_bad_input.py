"""Issue 7: bad input gets one clear sentence and changes nothing; failures and cancels roll back."""

import contextlib

import bpy
import pytest

from blender_checks import image_array, material_snapshot, mesh_snapshot
from blender_scenes import add_object, suzanne
from package import seamless_ao
from seamless_ao.core.errors import BakeCancelled, SeamlessAOError
from seamless_ao.operators.poll import selection_problem
from seamless_ao.operators.adapters.writes import Transaction
from seamless_ao.shaders.material import enable_nodes

FAST = dict(image_size=256, rays=8)


#: Where a write phase can break: right after the Transaction method of that name.
STEPS = {"image": "image", "uv_maps": "uv_maps", "materials": "materials", "saved": "file"}


@contextlib.contextmanager
def failing_after(step):
    """``with failing_after(step):`` a bake's write phase raises right after that step, as a crash would."""
    with pytest.MonkeyPatch.context() as patch:
        original = getattr(Transaction, STEPS[step])

        def failing(self, *args, **kwargs):
            original(self, *args, **kwargs)
            raise RuntimeError("injected failure after step '{}'".format(step))
        patch.setattr(Transaction, STEPS[step], failing)
        yield


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
    assert selection_problem(bpy.context) == "Select a mesh object to bake"


def test_non_mesh_object(monkey):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    bpy.context.scene.collection.objects.link(camera)
    expect_refusal([camera], "'Camera' is not a mesh")


def test_instanced_collection_is_refused_with_what_to_do(monkey):
    """Issue 16, item 2: an instance's meshes are shared with every other instance, so it is refused."""
    props = bpy.data.collections.new("Props")
    props.objects.link(bpy.data.objects.new("Crate", bpy.data.meshes.new("Crate")))
    instance = bpy.data.objects.new("Props instance", None)
    instance.instance_type, instance.instance_collection = "COLLECTION", props
    bpy.context.scene.collection.objects.link(instance)
    expect_refusal([instance], "'Props instance' instances the collection 'Props'.*Make Instances Real")


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


def test_a_stack_that_leaves_no_faces_is_refused(monkey):
    """Modifiers that leave nothing to bake (here a Geometry Nodes group whose output is empty) are refused as
    the object renders, not as its base mesh is (test_modifiers.py: every stack that leaves faces bakes)."""
    group = bpy.data.node_groups.new("Nothing", "GeometryNodeTree")
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    group.nodes.new("NodeGroupInput")
    group.nodes.new("NodeGroupOutput")
    monkey.modifiers.new("Nothing", "NODES").node_group = group
    expect_refusal([monkey], "'Suzanne' has no faces to bake as it renders")


def test_a_refusal_after_an_object_was_read_leaves_no_copy_of_it(monkey):
    """The first object is read, and its evaluated mesh copied for the ray caster, before the second is found
    to leave no faces: the copy goes with the refusal (blend_state counts every mesh)."""
    bpy.ops.mesh.primitive_cube_add(location=(4.0, 0.0, 0.0))
    cube = bpy.context.active_object
    group = bpy.data.node_groups.new("Nothing", "GeometryNodeTree")
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    monkey.modifiers.new("Nothing", "NODES").node_group = group
    expect_refusal([cube, monkey], "'Suzanne' has no faces to bake as it renders")


def test_deforming_modifier_bakes_the_evaluated_shape(fresh_scene, addon):
    """A box lifted far above a floor slab (one mesh) and brought down over it by a Displace modifier on the
    box's vertex group: the bake must see the box where the modifier puts it.  Read from the base mesh, the
    floor under the box would be open; baked as evaluated, what the material shows on the evaluated surface
    is within the accuracy limits of the plain reference computed on that surface."""
    import numpy as np
    from accuracy import P99_LIMIT, RMSE_LIMIT, errors, reference_ao, shown_seamless, surface_samples
    from blender_scenes import mesh_from_arrays
    from meshes import box
    from seamless_ao.operators.adapters.mesh_data import read_triangles

    floor = box(size=(4.0, 4.0, 0.2), center=(0.0, 0.0, -0.1), subdivisions=8)
    lifted = box(size=(1.0, 1.0, 1.0), center=(0.0, 0.0, 6.0), subdivisions=4)
    positions = np.vstack([floor[0], lifted[0]])
    triangles = np.vstack([floor[1], lifted[1] + len(floor[0])])
    ob = add_object("Deformed", mesh_from_arrays("Deformed", positions, triangles))
    group = ob.vertex_groups.new(name="lift")
    group.add(list(range(len(floor[0]), len(positions))), 1.0, "REPLACE")
    modifier = ob.modifiers.new("Displace", "DISPLACE")
    modifier.direction, modifier.mid_level, modifier.strength, modifier.vertex_group = "Z", 0.0, -5.2, "lift"
    bpy.context.view_layer.update()
    evaluated = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh, loops = read_triangles(evaluated.to_mesh())                             # the evaluated surface
    evaluated.to_mesh_clear()
    assert abs(mesh.positions[:, 2].max() - 1.3) < 1e-6                          # the box now floats at 0.3
    report = seamless_ao.bake([ob], image_size=512, rays=32)
    image = bpy.data.images[report.image]
    triangle, bary, normals = surface_samples(mesh, 1500, seed=4)
    shown = shown_seamless(ob, image, loops, triangle, bary, normals)
    reference = reference_ao(ob, mesh, triangle, bary, normals, rays=1024)
    points = np.einsum("kc,kcd->kd", bary, mesh.positions[mesh.triangles[triangle]])
    on_floor_under_box = (np.abs(points[:, :2]).max(axis=1) < 0.4) & (np.abs(points[:, 2]) < 1e-6)
    assert on_floor_under_box.sum() >= 5 and reference[on_floor_under_box].max() < 0.6
    assert shown[on_floor_under_box].max() < 0.6
    rmse, p99 = errors(shown, reference)
    assert rmse <= RMSE_LIMIT and p99 <= P99_LIMIT, (rmse, p99)


@pytest.mark.parametrize("step", ["image", "uv_maps", "materials"])
def test_injected_failure_changes_nothing(monkey, step):
    before = blend_state()
    with failing_after(step), pytest.raises(RuntimeError, match="injected failure"):
        seamless_ao.bake([monkey], **FAST)
    assert blend_state() == before


@pytest.mark.parametrize("step", ["image", "uv_maps", "materials"])
def test_failed_rebake_restores_the_previous_bake(monkey, step):
    seamless_ao.bake([monkey], **FAST)
    before = blend_state()
    with failing_after(step), pytest.raises(RuntimeError):
        seamless_ao.bake([monkey], image_size=512, rays=4, seed=9)
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


def edit_midway(change):
    """A progress callback that calls ``change()`` once the rays are being cast."""
    done = []

    def progress(fraction, message):
        if not done and message.startswith("Casting rays"):
            done.append(change())
    return progress


@pytest.mark.parametrize("edit", ["move a vertex", "delete a face", "enter Edit Mode"])
def test_edits_during_the_bake_cancel_it_cleanly(monkey, edit):
    """Issue 16, item 1: the interactive bake lets the user work while rays are cast; a bake whose
    object was edited meanwhile must not write stale UVs into the edited mesh."""
    import bmesh

    def change():
        if edit == "move a vertex":
            monkey.data.vertices[0].co.x += 0.1
        elif edit == "delete a face":
            mesh = bmesh.new()
            mesh.from_mesh(monkey.data)
            mesh.faces.ensure_lookup_table()
            bmesh.ops.delete(mesh, geom=[mesh.faces[0]], context="FACES_ONLY")
            mesh.to_mesh(monkey.data)
            mesh.free()
        else:
            bpy.ops.object.mode_set(mode="EDIT")
        return True

    with pytest.raises(SeamlessAOError, match="'Suzanne' was edited during the bake"):
        seamless_ao.bake([monkey], progress=edit_midway(change), **FAST)
    if monkey.mode == "EDIT":
        bpy.ops.object.mode_set(mode="OBJECT")
    assert not any(name in monkey.data.uv_layers for name in ("AO_X", "AO_Y", "AO_Z"))
    assert "Suzanne_AO" not in bpy.data.images and "Seamless AO" not in bpy.data.node_groups


def test_deleting_the_object_during_the_bake_cancels_it_cleanly(monkey):
    mesh = monkey.data

    def change():
        bpy.data.objects.remove(monkey)
        return True

    with pytest.raises(SeamlessAOError, match="deleted or undone during the bake"):
        seamless_ao.bake([monkey], progress=edit_midway(change), **FAST)
    assert not any(name in mesh.uv_layers for name in ("AO_X", "AO_Y", "AO_Z"))
    assert "Suzanne_AO" not in bpy.data.images and "Seamless AO" not in bpy.data.node_groups


def test_failed_bake_puts_back_an_older_node_group_it_rebuilt(monkey):
    """Issue 16, item 4: a bake that rebuilds an older ``Seamless AO`` group and then fails restores
    the old group, for every material using it."""
    from seamless_ao.core.keys import GROUP_NAME, VERSION_KEY
    seamless_ao.bake([monkey], **FAST)
    group = bpy.data.node_groups[GROUP_NAME]
    group[VERSION_KEY] = 0
    group.nodes.clear()
    group.nodes.new("NodeFrame").name = "from an older add-on"
    before = blend_state()
    with failing_after("materials"), pytest.raises(RuntimeError, match="injected failure"):
        seamless_ao.bake([monkey], image_size=512, rays=4, seed=9)
    assert blend_state() == before
    group = bpy.data.node_groups[GROUP_NAME]
    assert group[VERSION_KEY] == 0 and [n.name for n in group.nodes] == ["from an older add-on"]
    users = [n for m in bpy.data.materials if m.node_tree for n in m.node_tree.nodes
             if n.bl_idname == "ShaderNodeGroup"]
    assert users and all(n.node_tree == group for n in users)
    seamless_ao.bake([monkey], **FAST)                   # and a bake that succeeds leaves no copy behind
    assert [g.name for g in bpy.data.node_groups] == [GROUP_NAME]


@pytest.mark.parametrize("existing", [False, True])
def test_failed_bake_removes_or_restores_the_image_file_it_saved(monkey, tmp_path, existing):
    """Issue 16, item 4: ``save_image`` writes a file outside the .blend; a bake failing after
    writing it removes the new file, or puts back the one that was there."""
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "scene.blend"))
    path = tmp_path / "Suzanne_AO.png"
    if existing:
        path.write_bytes(b"an earlier bake's file")
    with failing_after("saved"), pytest.raises(RuntimeError, match="injected failure"):
        seamless_ao.bake([monkey], save_image="PNG", **FAST)
    if existing:
        assert path.read_bytes() == b"an earlier bake's file"
    else:
        assert not path.exists()
    assert "Suzanne_AO" not in bpy.data.images
