"""The Cycles ray caster (operators/adapters/cycles_caster.py): Cycles' AO at given points against a closed
form, and a whole bake against the Geometry Nodes caster's."""

import numpy as np
import pytest

from accuracy import errors, reference_ao, shown_seamless, surface_samples
from blender_checks import image_array
from blender_scenes import suzanne
from seamless_ao.core.rays.ray_setup import AOParams
from seamless_ao.operators.adapters.casters import CyclesCaster


@pytest.mark.parametrize("reach", [2.0, 4.0])
def test_cycles_ao_under_a_ceiling_is_the_closed_form(fresh_scene, reach):
    """Points on z = 0 facing up under a wide ceiling at z = 1: a cosine-distributed ray meets it within
    ``reach`` when cos(theta) >= 1 / reach, which a fraction 1 - 1 / reach² of them do, so the open
    fraction is 1 / reach².  Points facing down see nothing: open 1."""
    ceiling = np.array([[-60.0, -60.0, 1.0], [60.0, -60.0, 1.0], [60.0, 60.0, 1.0], [-60.0, 60.0, 1.0]])
    caster = CyclesCaster(ceiling, np.array([[0, 2, 1], [0, 3, 2]]))
    try:
        rng = np.random.default_rng(0)
        count = 600
        points = np.column_stack([rng.uniform(-1.0, 1.0, (count, 2)), np.zeros(count)])
        up = np.tile([0.0, 0.0, 1.0], (count, 1))
        down = -up
        normals = np.concatenate([up[: count // 2], down[count // 2:]])
        params = AOParams(rays=256, max_distance=reach, offset=1e-4)
        open_fraction = caster.ambient_occlusion(points, normals, normals, 256, params)
    finally:
        caster.free()
    assert open_fraction.shape == (count,) and np.isfinite(open_fraction).all()
    expected = 1.0 / reach**2
    under = open_fraction[: count // 2]
    # binomial noise of one point: sqrt(p (1 - p) / 256) <= 0.031; of the mean of 300 points: <= 0.002
    assert abs(under.mean() - expected) < 0.01, (under.mean(), expected)
    assert np.abs(under - expected).max() < 0.2
    assert np.allclose(open_fraction[count // 2:], 1.0)


def test_done_casting_the_cycles_caster_drops_the_raycast_set_up_and_still_bakes_and_casts(fresh_scene):
    """casting_done: the points, their node group and the occluder mesh the Raycast node built its BVH for
    are removed, a new mesh of the same triangles (and sealed flags) takes the occluder's place; Cycles
    still sees the ceiling, a later cast sets the node up again and hits where it hit before, and free()
    leaves no datablock of the caster's."""
    import bpy

    from seamless_ao.core.keys import TEMP_PREFIX

    ceiling = np.array([[-60.0, -60.0, 1.0], [60.0, -60.0, 1.0], [60.0, 60.0, 1.0], [-60.0, 60.0, 1.0]])
    caster = CyclesCaster(ceiling, np.array([[0, 2, 1], [0, 3, 2]]), np.array([True, False]))
    try:
        origins = np.column_stack([np.linspace(-1.0, 1.0, 8), np.zeros(8), np.zeros(8)])
        up = np.tile([0.0, 0.0, 1.0], (8, 1))
        before = caster.cast(origins, up, 5.0)
        raycast = [caster.points.name, caster.points_mesh.name, caster.group.name]
        old_mesh = caster.occluder.data.name
        caster.casting_done()
        assert caster.points is None and raycast[0] not in bpy.data.objects
        assert raycast[1] not in bpy.data.meshes and raycast[2] not in bpy.data.node_groups
        assert old_mesh not in bpy.data.meshes
        mesh = caster.occluder.data
        assert len(mesh.polygons) == 2 and len(mesh.vertices) == 4
        flags = np.empty(2, dtype=np.float32)
        mesh.attributes["sealed"].data.foreach_get("value", flags)
        assert flags.tolist() == [1.0, 0.0]
        open_fraction = caster.ambient_occlusion(origins, up, up, 64, AOParams(rays=64, max_distance=2.0, offset=1e-4))
        assert (np.abs(open_fraction - 0.25) < 0.2).all()       # 1 / reach²: the ceiling is still there
        after = caster.cast(origins, up, 5.0)
        for got, want in zip(after, before):
            assert np.array_equal(got, want)
        assert np.allclose(before[0], 1.0) and before[2].any() and not before[2].all()
    finally:
        caster.free()
    left = [d.name for kind in ("scenes", "objects", "meshes", "node_groups", "worlds")
            for d in getattr(bpy.data, kind) if d.name.startswith(TEMP_PREFIX)]
    assert not left, left


def test_a_gpu_bake_that_fails_is_baked_again_on_the_cpu_from_the_same_texel_mesh(fresh_scene, monkeypatch):
    """A GPU bake that raises (out of memory, a driver fault): the caster says so, turns to the CPU, bakes the
    same texel mesh with a material of its own, gets what a CPU bake gets, and leaves no datablock behind."""
    import bpy

    from seamless_ao.core.errors import SeamlessAOError
    from seamless_ao.core.keys import TEMP_PREFIX
    from seamless_ao.operators.adapters import cycles_caster

    ceiling = np.array([[-60.0, -60.0, 1.0], [60.0, -60.0, 1.0], [60.0, 60.0, 1.0], [-60.0, 60.0, 1.0]])
    points = np.column_stack([np.linspace(-1.0, 1.0, 50), np.zeros(50), np.zeros(50)])
    up = np.tile([0.0, 0.0, 1.0], (50, 1))
    params = AOParams(rays=64, max_distance=2.0, offset=1e-4, seed=3)
    plain = CyclesCaster(ceiling, np.array([[0, 2, 1], [0, 3, 2]]))
    try:
        expected = plain.ambient_occlusion(points, up, up, 64, params)
    finally:
        plain.free()
    real_bake, calls = cycles_caster.CyclesAmbientOcclusion._bake, []

    def failing_on_the_gpu(self, mesh, *args):
        calls.append((self.device, mesh.name, len(mesh.polygons)))
        if self.device == "GPU":
            raise SeamlessAOError("out of device memory")
        return real_bake(self, mesh, *args)

    monkeypatch.setattr(cycles_caster.CyclesAmbientOcclusion, "_bake", failing_on_the_gpu)
    caster = CyclesCaster(ceiling, np.array([[0, 2, 1], [0, 3, 2]]))
    try:
        caster.device = "GPU"
        got = caster.ambient_occlusion(points, up, up, 64, params)
        assert caster.device == "CPU"
        assert caster.warnings == ["Cycles could not bake on the GPU (out of device memory): it baked on the CPU"]
    finally:
        caster.free()
    assert [device for device, _, _ in calls] == ["GPU", "CPU"] and calls[0][1:] == calls[1][1:] == (calls[0][1], 50)
    assert np.array_equal(got, expected)
    left = [d.name for kind in ("scenes", "objects", "meshes", "materials", "images", "node_groups", "worlds")
            for d in getattr(bpy.data, kind) if d.name.startswith(TEMP_PREFIX)]
    assert not left, left


def test_a_cycles_bake_shows_the_geometry_nodes_bake_and_leaves_nothing_behind(addon, fresh_scene):
    """Suzanne on a floor, baked with each caster: the same AO within the rays' noise, every datablock the
    Cycles caster made removed, and the scene's render engine and world as they were."""
    import bpy

    from seamless_ao.core.keys import TEMP_PREFIX

    head = suzanne(1)
    bpy.ops.mesh.primitive_plane_add(size=4.0, location=(0.0, 0.0, -0.8))
    floor = bpy.context.active_object
    scene = bpy.context.scene
    engine, world = scene.render.engine, scene.world
    counts = {kind: len(getattr(bpy.data, kind)) for kind in ("scenes", "objects", "meshes", "images", "materials",
                                                              "worlds", "node_groups")}
    images = {}
    for caster in ("GEOMETRY_NODES", "CYCLES"):
        report = addon.bake([head, floor], image_size=256, rays=64, ray_caster=caster, denoise=False)
        images[caster] = image_array(bpy.data.images[report.image]).copy()
    assert scene.render.engine == engine and scene.world == world
    assert not [d.name for kind in counts for d in getattr(bpy.data, kind) if d.name.startswith(TEMP_PREFIX)]
    after = {kind: len(getattr(bpy.data, kind)) for kind in counts}
    # what the bake itself writes: its image and node group (and materials for objects that had none)
    assert after == dict(counts, images=counts["images"] + 1, node_groups=counts["node_groups"] + 1,
                         materials=after["materials"]), (counts, after)
    nodes, cycles = images["GEOMETRY_NODES"], images["CYCLES"]
    shown = (nodes > 0) | (cycles > 0)
    assert shown.sum() > 10000
    # Cycles cast the rays after the pilot (both parts have over core/rays/job.py's BULK_LEAST_RAYS of them):
    # with the node's rays alone the two images would be the same, ray for ray
    assert (cycles != nodes).mean() > 0.5
    gap = cycles[shown] - nodes[shown]
    # 64 rays: a texel's noise is about 0.06 at AO 1/2. The means differ by a convention, not by noise: the
    # node mirrors a ray that leaves below the face to above it, Cycles (and the plain reference) do not,
    # so Cycles is a little darker where shading and face normals part; which of the two is nearer the
    # reference is the next test's question.
    assert abs(gap.mean()) < 0.02, gap.mean()
    assert np.sqrt((gap * gap).mean()) < 0.08
    assert np.isfinite(cycles).all() and cycles.min() >= 0.0 and cycles.max() <= 1.0


def test_a_cancelled_cycles_bake_leaves_nothing_behind(addon, fresh_scene):
    """Cancelled between two of Cycles' steps (after the pilot rays): no temporary datablock is left, and
    the object has none of the bake's UV maps."""
    import bpy

    from seamless_ao.core.rays import job
    from seamless_ao.core.errors import BakeCancelled
    from seamless_ao.core.keys import TEMP_PREFIX

    head = suzanne(2)
    steps = []
    kept = job.BULK_FIRST_RAYS
    job.BULK_FIRST_RAYS = 1 << 16                        # many small steps
    try:
        addon.bake([head], image_size=256, rays=64, ray_caster="CYCLES",
                   should_cancel=lambda: len(steps) >= 3,            # the pilot's step, then two of Cycles'
                   progress=lambda fraction, message: steps.append(message) if message.startswith("Casting") else None)
    except BakeCancelled:
        pass
    else:
        raise AssertionError("the bake was not cancelled")
    finally:
        job.BULK_FIRST_RAYS = kept
    assert not [d.name for kind in ("scenes", "objects", "meshes", "images", "materials", "worlds", "node_groups")
                for d in getattr(bpy.data, kind) if d.name.startswith(TEMP_PREFIX)]
    assert not [layer.name for layer in head.data.uv_layers if layer.name.startswith("AO_")]


def test_a_cycles_bake_is_as_near_the_plain_reference_as_a_geometry_nodes_bake(addon, fresh_scene):
    """Suzanne subdivided once and shaded smooth (her shading normals part from her faces most), baked with
    each caster: at 1,000 random visible points, what the material shows against the plain reference
    (tests/support/plain_reference.py, no code shared with either caster).  Cycles casts most rays here, and
    its RMSE and its mean error are no worse than the node's."""
    import bpy

    from seamless_ao.operators.adapters.mesh_data import read_triangles

    head = suzanne(1)
    mesh, loops = read_triangles(head.data)
    triangle, bary, normals = surface_samples(mesh, 1000, seed=7)
    reference = reference_ao(head, mesh, triangle, bary, normals, rays=1024, seed=3)
    measured = {}
    for caster in ("GEOMETRY_NODES", "CYCLES"):
        report = addon.bake([head], image_size=256, rays=64, ray_caster=caster, denoise=False)
        shown = shown_seamless(head, bpy.data.images[report.image], loops, triangle, bary, normals)
        assert np.isfinite(shown).all()
        measured[caster] = (errors(shown, reference)[0], float((shown - reference).mean()))
    (nodes_rmse, nodes_mean), (cycles_rmse, cycles_mean) = measured["GEOMETRY_NODES"], measured["CYCLES"]
    # the reference's own noise at 1024 rays is about 0.016 per point at AO 1/2, 0.0005 in the mean
    assert cycles_rmse <= nodes_rmse + 0.003, measured
    assert abs(cycles_mean) <= abs(nodes_mean) + 0.003, measured


def test_the_automatic_caster_takes_cycles_where_it_can_and_the_node_where_it_cannot(addon, fresh_scene):
    """Ray Caster Automatic: Cycles at classic AO with rays beyond the pilot; with a falloff (which Cycles'
    AO cannot follow) or no rays beyond the pilot it bakes with the node, and refuses neither.  With too few
    rays after the pilot for Cycles to pay off (core/rays/job.py's BULK_LEAST_RAYS) the node casts them all, and
    the report says so."""
    from seamless_ao.core.rays.job import BULK_LEAST_RAYS
    from seamless_ao.core.rays.cycles_rules import BULK_PILOT_RAYS
    from seamless_ao.operators.adapters.casters import NodesCaster

    head = suzanne(1)
    chosen = {}
    for name, settings in (("classic", {}), ("falloff", dict(falloff="LINEAR")),
                           ("pilot only", dict(rays=BULK_PILOT_RAYS)), ("few", dict(rays=BULK_PILOT_RAYS + 2))):
        report = addon.bake([head], **dict(dict(image_size=256, rays=32, ray_caster="AUTOMATIC"), **settings))
        chosen[name] = report.caster
        if name == "classic":
            assert report.texels * (32 - BULK_PILOT_RAYS) > BULK_LEAST_RAYS > report.texels * 2
    assert chosen == {"classic": CyclesCaster.name, "falloff": NodesCaster.name,
                      "pilot only": NodesCaster.name, "few": NodesCaster.name}, chosen
    # one name per caster: the Ray Caster setting's
    assert (CyclesCaster.name, NodesCaster.name) == ("CYCLES", "GEOMETRY_NODES")
    assert CyclesCaster.bakes_whole_texels and not NodesCaster.bakes_whole_texels
    assert CyclesCaster.pilot_name == NodesCaster.name
    assert "rays cast by Geometry Nodes (first rays) and Cycles" in addon.bake(
        [head], image_size=256, rays=32).summary()



def test_with_cycles_turned_off_automatic_bakes_with_the_node_and_a_chosen_cycles_says_why(addon, fresh_scene):
    """Cycles' add-on disabled in the Preferences: Ray Caster Automatic bakes with the node and the panel says
    why; the Cycles caster chosen by name refuses with a sentence, and leaves the mesh as it was."""
    import addon_utils
    import bpy

    from seamless_ao.core.errors import SeamlessAOError
    from seamless_ao.operators.adapters.casters import NodesCaster
    from seamless_ao.operators.adapters.scene_settings import automatic_caster_line

    head = suzanne(1)
    layers = [uv.name for uv in head.data.uv_layers]
    addon_utils.disable("cycles", default_set=False)
    try:
        assert not hasattr(bpy.types.Scene, "cycles")
        assert automatic_caster_line(bpy.context.scene.seamless_ao) == (
            "Automatic: Geometry Nodes, Cycles is not enabled in this Blender")
        assert addon.bake([head], image_size=256, rays=16).caster == NodesCaster.name
        addon.clear([head])
        with pytest.raises(SeamlessAOError, match="needs the Cycles render engine, which is not enabled"):
            addon.bake([head], image_size=256, rays=16, ray_caster="CYCLES")
        assert [uv.name for uv in head.data.uv_layers] == layers
    finally:
        addon_utils.enable("cycles", default_set=False)
    assert hasattr(bpy.types.Scene, "cycles")

def test_a_ray_caster_saved_before_automatic_existed_reads_back_as_it_was_chosen(addon, fresh_scene):
    """A .blend stores the Ray Caster as its item's position: those of Geometry Nodes, Python BVH and Cycles,
    as files saved before Automatic was added hold them, still read as those casters; a scene that never set
    it reads the default, Automatic."""
    import bpy

    settings = bpy.context.scene.seamless_ao
    assert settings.ray_caster == "AUTOMATIC"
    for stored, chosen in enumerate(("GEOMETRY_NODES", "PYTHON_BVH", "CYCLES")):
        settings["ray_caster"] = stored                  # what loading such a file sets
        assert settings.ray_caster == chosen


def test_the_panel_says_what_automatic_will_cast_with_and_why(addon, fresh_scene):
    """The Occluders panel's line under Ray Caster, read from the scene's settings as the panel reads them:
    Cycles at the defaults, the node with the reason when a setting (or the ray count) rules Cycles out,
    nothing for a chosen caster or invalid settings."""
    import bpy

    from seamless_ao.operators.adapters.scene_settings import automatic_caster_line

    settings = bpy.context.scene.seamless_ao
    assert automatic_caster_line(settings) == "Automatic: Cycles, all but each texel's first 4 rays"
    settings.falloff = "LINEAR"
    assert automatic_caster_line(settings) == "Automatic: Geometry Nodes, Cycles' AO has no falloff"
    settings.falloff, settings.quality, settings.rays = "NONE", "CUSTOM", 4
    assert automatic_caster_line(settings).startswith("Automatic: Geometry Nodes, the node casts")
    settings.auto_distance, settings.max_distance = False, 0.0          # invalid: the bake will say why
    assert automatic_caster_line(settings) is None
    settings.auto_distance, settings.ray_caster = True, "GEOMETRY_NODES"
    assert automatic_caster_line(settings) is None
