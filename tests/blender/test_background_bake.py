"""Issue 51: the window's bake runs its pipeline in a background process of ours, so the interface stays
live; what it writes is what a bake in this process writes, and a cancelled or failed one writes nothing."""

import os

import bpy
import numpy as np
import pytest

from package import seamless_ao

from seamless_ao.core.errors import SeamlessAOError
from seamless_ao.core.other_processes.handoff import read_job, write_job
from seamless_ao.operators.adapters.stack import viewport_helper_of
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.settings import BakeSettings
from seamless_ao.operators.adapters.session import BakeSession

#: The Geometry Nodes caster casts the same rays run after run (Cycles' threads do not), so the two
#: processes must agree to the bit.
SETTINGS = BakeSettings(quality="CUSTOM", rays=16, image_size=256, ray_caster="GEOMETRY_NODES")


def suzanne_on_a_plane():
    """Suzanne with Blender's default Subdivision (viewport 1, render 2) on a plane: the artist's scene."""
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 1.0))
    suzanne = bpy.context.active_object
    suzanne.modifiers.new("Subdivision", "SUBSURF")
    bpy.ops.object.shade_smooth()
    bpy.ops.mesh.primitive_plane_add(size=6.0)
    return [suzanne, bpy.context.active_object]


def written(session, objects):
    """The image's pixels and every UV map the bake wrote (the plane's on its mesh; the UV maps of the
    viewport's surface of Suzanne, whose Subdivision levels differ, on the stack's viewport helper)."""
    image = bpy.data.images[session.report.image]
    pixels = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)
    uv = np.empty(2 * len(objects[1].data.loops))
    maps = []
    for name in ("AO_X", "AO_Y", "AO_Z"):
        objects[1].data.uv_layers[name].data.foreach_get("uv", uv)
        maps.append(uv.copy())
    shown = viewport_helper_of(objects[0]).data
    for name in ("AO_X", "AO_Y", "AO_Z"):
        uv = np.empty(2 * len(shown.loops))
        shown.uv_layers[name].data.foreach_get("uv", uv)
        maps.append(uv)
    return pixels, maps


def datablocks():
    return {kind: sorted(getattr(bpy.data, kind).keys()) for kind in ("objects", "meshes", "images", "materials",
                                                                      "node_groups", "scenes")}


def test_a_background_bake_writes_what_a_bake_here_writes(addon, fresh_scene):
    results = []
    for background in (False, True):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        objects = suzanne_on_a_plane()
        session = BakeSession(objects, SETTINGS, background=background)
        for _ in session.steps():
            pass
        results.append(written(session, objects))
        if background:
            assert session.report.caster == "GEOMETRY_NODES" and session.report.texels > 10000
            assert not os.path.exists(session.process.folder), "the process's folder was left behind"
    (pixels_here, uv_here), (pixels_there, uv_there) = results
    assert np.array_equal(pixels_here, pixels_there)
    assert all(np.array_equal(a, b) for a, b in zip(uv_here, uv_there))



def test_with_cycles_turned_off_here_the_background_process_bakes_with_the_node_too(addon, fresh_scene):
    """The process starts from factory settings, where Cycles is on: Ray Caster Automatic is resolved in the
    window, where the user turned it off, so both say the same caster."""
    import addon_utils

    objects = suzanne_on_a_plane()
    addon_utils.disable("cycles", default_set=False)
    try:
        session = BakeSession(objects, SETTINGS.replace(ray_caster="AUTOMATIC"), background=True)
        for _ in session.steps():
            pass
    finally:
        addon_utils.enable("cycles", default_set=False)
    assert session.report.caster == "GEOMETRY_NODES"

def test_a_background_bake_stopped_midway_ends_its_process_and_writes_nothing(addon, fresh_scene):
    objects = suzanne_on_a_plane()
    before = datablocks()
    session = BakeSession(objects, SETTINGS.replace(rays=256, image_size=1024), background=True)
    steps = session.steps()
    for fraction, message in steps:
        if session.process is not None and message.startswith("Casting rays"):
            break
    else:
        pytest.fail("the background bake never reported casting rays")
    process, folder = session.process.process, session.process.folder
    steps.close()                                       # what the operator's cancel() does
    assert process.poll() is not None, "the bake process still runs"
    assert not os.path.exists(folder)
    assert datablocks() == before
    assert "AO_X" not in objects[1].data.uv_layers


def test_a_refusal_in_the_background_process_reaches_the_user_as_its_sentence(addon, fresh_scene):
    objects = suzanne_on_a_plane()
    before = datablocks()
    session = BakeSession(objects, SETTINGS.replace(memory_budget_mb=64, image_size=8192), background=True)
    with pytest.raises(SeamlessAOError, match="memory"):
        for _ in session.steps():
            pass
    assert datablocks() == before


def test_a_job_reads_back_as_it_was_written(tmp_path):
    rng = np.random.default_rng(5)
    mesh = TriangleMesh.from_triangles(rng.random((30, 3)), rng.integers(0, 30, (40, 3)))
    occluders = [[(rng.random((4, 3)), np.array([[0, 1, 2], [1, 2, 3]]))]]
    surface = (rng.random((6, 3)), np.array([0, 1, 2, 3, 2, 1, 4, 5]), np.array([0, 4]))
    # the second with the islands and side edges its reader found, the first without
    with_islands = TriangleMesh(mesh.positions, mesh.triangles, mesh.triangle_face, mesh.normals_as_read,
                                vertex_island=rng.integers(0, 5, 30), side_edge=rng.integers(0, 60, (40, 3)))
    write_job(str(tmp_path), [mesh, with_islands], [np.eye(4) * 2.0] * 2, occluders * 2, SETTINGS, [None, surface])
    meshes, matrices, near, settings, shown = read_job(str(tmp_path))
    assert shown[0] is None and all(np.array_equal(a, b) for a, b in zip(shown[1], surface))
    for name in ("vertex_island", "side_edge"):
        assert getattr(meshes[0], name) is None and np.array_equal(getattr(meshes[1], name), getattr(with_islands, name))
    for name in ("positions", "triangles", "triangle_face", "corner_normals", "stray", "triangle_area"):
        assert np.array_equal(getattr(meshes[0], name), getattr(mesh, name)), name
    assert meshes[0].face_count == mesh.face_count and meshes[0].scale == mesh.scale
    assert np.array_equal(matrices[0], np.eye(4) * 2.0)
    assert all(np.array_equal(a, b) for a, b in zip(near[0][0], occluders[0][0]))
    assert settings == SETTINGS
