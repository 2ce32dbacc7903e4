"""The Geometry Nodes ray caster (operators/casters.py) against a closed form and, hit for hit, against
core's BVHTree caster."""

import numpy as np
import pytest

from blender_scenes import suzanne
from seamless_ao.core.rays.ray_setup import BVHCaster
from seamless_ao.operators.adapters import casters
from seamless_ao.operators.adapters.casters import NodesCaster
from seamless_ao.operators.adapters.mesh_data import read_triangles


def random_rays(seed, count, centre=(0.0, 0.0, 0.0)):
    """``count`` rays (origins, unit directions) (count, 3) each, from a box 3 units wide about ``centre``."""
    rng = np.random.default_rng(seed)
    origins = rng.uniform(-1.5, 1.5, (count, 3)) + centre
    directions = rng.normal(size=(count, 3))
    return origins, directions / np.linalg.norm(directions, axis=1, keepdims=True)


def counted_caster(positions, triangles, flags):
    """A NodesCaster and the list it appends the ray count of each evaluation of its node to."""
    caster, evaluated = NodesCaster(positions, triangles, flags), []
    evaluate = caster._evaluate
    caster._evaluate = lambda o, d, m: evaluated.append(len(o)) or evaluate(o, d, m)
    return caster, evaluated


def test_nodes_caster_hits_a_plane_where_the_closed_form_says(fresh_scene):
    """Rays from z = 0 to a plane z = 1 facing down: distance 1 / cos(theta), front face; the plane is
    missed by rays longer than the maximum distance."""
    positions = np.array([[-50.0, -50.0, 1.0], [-50.0, 50.0, 1.0], [50.0, 50.0, 1.0], [50.0, -50.0, 1.0]])
    caster = NodesCaster(positions, np.array([[0, 1, 2], [0, 2, 3]]))
    try:
        rng = np.random.default_rng(0)
        cos_theta = rng.uniform(0.2, 1.0, 500)
        angle = rng.uniform(0.0, 2 * np.pi, 500)
        sin_theta = np.sqrt(1 - cos_theta**2)
        directions = np.stack([sin_theta * np.cos(angle), sin_theta * np.sin(angle), cos_theta], axis=1)
        origins = np.column_stack([rng.uniform(-1, 1, (500, 2)), np.zeros(500)])
        distance, facing, sealed = caster.cast(origins, directions, 3.0)
        reach = 1.0 / cos_theta <= 3.0
        assert np.allclose(distance[reach], 1.0 / cos_theta[reach], rtol=1e-5)
        assert np.isinf(distance[~reach]).all() and (~reach).sum() > 50
        assert (facing[reach] < 0).all()                                  # hit from the front
        assert not sealed.any()                                           # no sealed triangle given
    finally:
        caster.free()


@pytest.mark.parametrize("flagged, domain", [("triangle", "FACE"), ("piece", "POINT")])
def test_nodes_caster_agrees_with_the_bvh_caster_hit_for_hit(fresh_scene, flagged, domain):
    """Distance, facing and the sealed flag of the hit triangle: here every odd triangle, so a caster
    that read the flag of another triangle, or none, would disagree on half the hits; or, as the sealed test
    flags them, whole pieces (of two Suzannes side by side, the second), which the caster keeps on the vertices."""
    mesh, _ = read_triangles(suzanne(1).data)
    origins, directions = random_rays(1, 4000)
    positions, triangles = mesh.positions, mesh.triangles
    if flagged == "triangle":
        flags = np.arange(len(triangles)) % 2 == 1
    else:
        positions = np.concatenate([positions - (0.7, 0.0, 0.0), positions + (0.7, 0.0, 0.0)])
        triangles = np.concatenate([triangles, triangles + len(mesh.positions)])
        flags = np.arange(len(triangles)) >= len(mesh.triangles)
    nodes = NodesCaster(positions, triangles, flags)
    try:
        assert nodes.occluder.data.attributes["sealed"].domain == domain
        distance, facing, sealed = nodes.cast(origins, directions, 2.0)
    finally:
        nodes.free()
    expected_distance, expected_facing, expected_sealed = BVHCaster(positions, triangles, flags).cast(
        origins, directions, 2.0)
    hit = np.isfinite(expected_distance)
    assert 500 < hit.sum() < 3500
    assert 0.3 < expected_sealed[hit].mean() < 0.7 and not expected_sealed[~hit].any()
    agree = (np.isfinite(distance) == hit) & (sealed == expected_sealed)
    agree[hit] &= np.isclose(distance[hit], expected_distance[hit], rtol=1e-4, atol=1e-5)
    agree[hit] &= np.sign(facing[hit]) == np.sign(expected_facing[hit])
    assert agree.mean() > 0.999, agree.mean()                  # a ray grazing an edge may go either way


def test_a_big_occluders_bvh_is_built_by_one_ray_before_its_first_batch_and_changes_no_hit(fresh_scene, monkeypatch):
    """From BUILD_ALONE_FROM_TRIANGLES (made small here) the first batch is preceded by a cast of its first ray
    alone, once per BVH: again after the Raycast set-up is let go of (the occluder's copy drops the BVH).  The
    hits are those of a caster that casts the batch at once.  (Where the node keeps its BVH: 4.4 on.)"""
    monkeypatch.setattr(casters, "RAYCAST_KEEPS_BVH", True)
    mesh, _ = read_triangles(suzanne(1).data)
    origins, directions = random_rays(2, 3000)
    flags = np.arange(len(mesh.triangles)) % 3 == 0
    results = {}
    for least in (len(mesh.triangles) + 1, len(mesh.triangles)):
        monkeypatch.setattr(casters, "BUILD_ALONE_FROM_TRIANGLES", least)
        caster, evaluated = counted_caster(mesh.positions, mesh.triangles, flags)
        try:
            first = caster.cast(origins, directions, 2.0)
            again = caster.cast(origins[:100], directions[:100], 2.0)
            caster._release_raycast()
            after_release = caster.cast(origins, directions, 2.0)
        finally:
            caster.free()
        for one, other in zip(first, after_release):
            assert np.array_equal(one, other)
        for one, other in zip(again, first):
            assert np.array_equal(one, other[:100])
        results[least] = (evaluated, first)
    (below, below_hits), (above, above_hits) = results.values()
    assert below == [3000, 100, 3000]
    assert above == [1, 3000, 100, 1, 3000]
    for one, other in zip(below_hits, above_hits):
        assert np.array_equal(one, other)
    assert np.isfinite(below_hits[0]).sum() > 500


def test_where_the_node_builds_its_bvh_at_every_batch_small_batches_are_cast_one_ray_at_a_time(fresh_scene,
                                                                                                 monkeypatch):
    """Blender 4.2 and 4.3 (made so here): no one-ray build before the first batch (it would only build the BVH
    once more); a batch under single_rays_below (here 1000) rays is cast on one mathutils BVH, built at the
    first such batch and let go of with the Raycast set-up, and hits what the node hits."""
    monkeypatch.setattr(casters, "RAYCAST_KEEPS_BVH", False)
    monkeypatch.setattr(casters, "BUILD_ALONE_FROM_TRIANGLES", 1)
    mesh, _ = read_triangles(suzanne(1).data)
    monkeypatch.setattr(casters, "single_rays_below", lambda triangles: 1000)
    origins, directions = random_rays(4, 3000)
    flags = np.arange(len(mesh.triangles)) % 2 == 1
    caster, evaluated = counted_caster(mesh.positions, mesh.triangles, flags)
    try:
        batch = caster.cast(origins, directions, 2.0)
        single = [caster.cast(origins[:500], directions[:500], 2.0)]
        tree = caster.single.tree
        single.append(caster.cast(origins[500:999], directions[500:999], 2.0))
        assert evaluated == [3000] and caster.single.tree is tree                  # one mathutils BVH
        caster._release_raycast()
        assert caster.single is None
    finally:
        caster.free()
    distance, facing, sealed = (np.concatenate(parts) for parts in zip(*single))
    hit = np.isfinite(batch[0][:999])
    assert 100 < hit.sum() < 900 and 0.3 < batch[2][:999][hit].mean() < 0.7
    agree = (np.isfinite(distance) == hit) & (sealed == batch[2][:999])
    agree[hit] &= np.isclose(distance[hit], batch[0][:999][hit], rtol=1e-4, atol=1e-5)
    agree[hit] &= np.sign(facing[hit]) == np.sign(batch[1][:999][hit])
    assert agree.mean() > 0.995, agree.mean()


def test_single_rays_take_batches_of_up_to_a_tenth_of_the_triangles_on_two_cores_and_fewer_on_more():
    assert casters.single_rays_below(1_000_000, cores=2) == pytest.approx(100_000)
    assert casters.single_rays_below(1_000_000, cores=1) == pytest.approx(100_000)
    assert casters.single_rays_below(1_000_000, cores=8) == pytest.approx(25_000)
    assert casters.single_rays_below(1_000_000) > 0


@pytest.mark.parametrize("single", [False, True], ids=["node", "single rays"])
def test_a_caster_given_the_copy_of_what_was_read_hits_what_a_mesh_built_anew_hits(fresh_scene, monkeypatch, single):
    """Suzanne subdivided once (quads: Blender's triangulation of them is what the bake read), a flag per
    piece: a caster that takes over the copy of her evaluated mesh (moved to ray space: here 3 units and
    turned) hits what a caster of a mesh built from the triangles hits, sealed flags included, to the bit; the
    copy is gone when the caster is freed.  Also where the node would build its BVH at every batch and each
    batch is cast one ray at a time (a mathutils BVH of the faces, quads or triangles)."""
    import bpy

    if single:
        monkeypatch.setattr(casters, "RAYCAST_KEEPS_BVH", False)
        monkeypatch.setattr(casters, "single_rays_below", lambda triangles: np.inf)

    from seamless_ao.core.mesh.weld import vertex_pieces
    from seamless_ao.operators.adapters.mesh_data import occluder_copy, read_object

    head = suzanne(1)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    arrays = read_object(head, depsgraph)[0]
    assert len(head.data.polygons) < len(arrays.triangles)                     # quads, two triangles each
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    positions = np.asarray(arrays.positions, dtype=np.float64) @ turn.T + [3.0, 0.0, 0.0]
    triangles = np.asarray(arrays.triangles)
    # a flag per piece, as the sealed test gives (hers are all sealed): her head's on, her eyes' off
    piece = vertex_pieces(positions, triangles)[triangles[:, 0]]
    sealed = piece == np.bincount(piece).argmax()
    assert 0 < sealed.sum() < len(sealed)
    origins, directions = random_rays(3, 4000, centre=(3.0, 0.0, 0.0))
    hits = []
    for source in (None, occluder_copy(head, depsgraph, arrays)):
        caster = NodesCaster(positions, triangles, sealed, source=source)
        caster._evaluate = None if single else caster._evaluate         # single rays never evaluate the node
        try:
            hits.append(caster.cast(origins, directions, 2.0))
        finally:
            caster.free()
        if source is not None:
            with pytest.raises(ReferenceError):
                source.mesh.name
    assert 500 < np.isfinite(hits[0][0]).sum() < 3500 and hits[0][2].any()
    for built, copied in zip(*hits):
        assert np.array_equal(built, copied)


def test_a_bake_casts_against_the_copy_where_its_occluders_are_the_mesh_alone(addon, fresh_scene, monkeypatch):
    """No occluder mesh is built anew for an object baked alone (the caster takes the copy of what was read);
    one is where scene occluders join it, or where its matrix mirrors it (the triangles are wound anew)."""
    import bpy

    built = []
    make = casters.mesh_from_triangles
    monkeypatch.setattr(casters, "mesh_from_triangles", lambda *args: built.append(1) or make(*args))
    head = suzanne(1)
    addon.bake([head], image_size=256, rays=2)
    assert built == []
    bpy.ops.mesh.primitive_plane_add(size=6.0, location=(0.0, 0.0, -1.0))
    addon.bake([head], image_size=256, rays=2, use_scene_occluders=True)
    assert built == [1]
    head.scale.x = -1.0
    addon.bake([head], image_size=256, rays=2)
    assert built == [1, 1]


def test_blenders_islands_give_the_pieces_of_the_triangles_and_none_with_a_loose_edge(addon, fresh_scene,
                                                                                      monkeypatch):
    """Mesh Island on a copy of what was read: two boxes, one of them with every face its own vertices (an
    import's), and a loose vertex; the pieces from its islands are those the triangles make.  A loose edge
    joining the boxes would join their islands, which the triangles do not: no islands then.  A bake hands
    the islands to a mesh of ISLANDS_FROM_TRIANGLES triangles or more, and none to a smaller one."""
    import bpy

    import meshes
    from seamless_ao.core.keys import TEMP_PREFIX
    from seamless_ao.core.mesh import triangle_mesh
    from seamless_ao.core.mesh.weld import vertex_pieces
    from seamless_ao.operators.adapters.mesh_data import ISLANDS_FROM_TRIANGLES, vertex_islands

    positions, triangles = meshes.box(subdivisions=2)
    split_positions, split_triangles = meshes.split_vertices(positions + [3.0, 0.0, 0.0], triangles)
    points = np.vstack([positions, split_positions, [[9.0, 9.0, 9.0]]])
    faces = np.vstack([triangles, split_triangles + len(positions)])
    found = []
    for edges in ([], [(0, len(positions))]):
        mesh = bpy.data.meshes.new("boxes")
        mesh.from_pydata(points.tolist(), edges, faces.tolist())
        found.append(vertex_islands(mesh))
        bpy.data.meshes.remove(mesh)
    islands, none = found
    assert none is None
    assert len(islands) == len(points) and int(islands.max()) + 1 > len(split_triangles) + 2
    assert np.array_equal(vertex_pieces(points, faces, islands=islands), vertex_pieces(points, faces))
    assert not [d for kind in (bpy.data.scenes, bpy.data.objects, bpy.data.node_groups) for d in kind
                if d.name.startswith(TEMP_PREFIX)]
    given = []
    pieces = triangle_mesh.vertex_pieces
    monkeypatch.setattr(triangle_mesh, "vertex_pieces",
                        lambda *args, islands=None: given.append(islands) or pieces(*args, islands=islands))
    for level, given_islands in ((3, True), (1, False)):
        head = suzanne(level)
        assert (len(read_triangles(head.data)[0].triangles) >= ISLANDS_FROM_TRIANGLES) == given_islands
        given.clear()
        addon.bake([head], image_size=256, rays=1)
        assert given and all((islands is not None) == given_islands for islands in given)


def test_a_bake_of_many_objects_leaves_no_temporary_datablock(addon, fresh_scene):
    """Each object gets a caster (a scene, two objects, two meshes and a node group of its own); all of
    them go in one batch_remove after the rays, after a cancel too."""
    import bpy
    from seamless_ao.core.errors import BakeCancelled
    from seamless_ao.core.keys import TEMP_PREFIX

    def temporary():
        return [d.name for kind in (bpy.data.scenes, bpy.data.objects, bpy.data.meshes, bpy.data.node_groups)
                for d in kind if d.name.startswith(TEMP_PREFIX)]

    objects = []
    for k in range(6):
        bpy.ops.mesh.primitive_cube_add(size=0.8, location=(k, 0.0, 0.0))
        objects.append(bpy.context.active_object)
    before = (len(bpy.data.scenes), len(bpy.data.objects), len(bpy.data.meshes), len(bpy.data.node_groups))
    addon.bake(objects, image_size=256, rays=4, use_scene_occluders=True)
    assert temporary() == []
    assert (len(bpy.data.scenes), len(bpy.data.objects), len(bpy.data.meshes)) == before[:3]
    casting = []
    try:
        addon.bake(objects, image_size=256, rays=4, should_cancel=lambda: bool(casting),
                   progress=lambda fraction, message: casting.append(1) if message.startswith("Casting") else None)
    except BakeCancelled:
        pass
    else:
        raise AssertionError("the bake was not cancelled")
    assert casting and temporary() == []


def test_triangles_are_read_as_blenders_own_whether_every_face_is_a_triangle_or_not(fresh_scene):
    """An all-triangle mesh's triangles are its faces' corners in order, with no call per triangle; a mesh of
    quads, triangles and an n-gon goes through Blender's triangulation.  Either way: what loop_triangles says."""
    import bpy

    from seamless_ao.operators.adapters.mesh_data import triangle_loops

    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
    triangles_only = bpy.context.active_object.data
    bpy.ops.mesh.primitive_cylinder_add(vertices=7)              # 7 quads, two 7-gons
    mixed = bpy.context.active_object.data
    for mesh, all_triangles in ((triangles_only, True), (mixed, False)):
        assert (len(mesh.loops) == 3 * len(mesh.polygons)) == all_triangles
        mesh.calc_loop_triangles()
        blenders = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("loops", blenders)
        assert np.array_equal(triangle_loops(mesh), blenders.reshape(-1, 3))


def test_triangle_sides_are_numbered_by_blenders_edges_alike_exactly_where_they_join_the_same_vertices(fresh_scene):
    """Each side of Blender's triangles gets its edge's number (a quad's diagonal one of its own), so two sides
    share a number exactly when they join the same two vertices: on triangles, on quads and triangles
    (Suzanne, subdivided once), on a cube whose quads are bent (Blender picks each diagonal).  A mesh with an
    n-gon gets none."""
    import bpy

    from seamless_ao.operators.adapters.mesh_data import (loop_vertices, triangle_loops, triangle_polygons,
                                                          triangle_side_edges)

    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
    triangles_only = bpy.context.active_object.data
    mixed = suzanne(2).data
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object.data
    cube.vertices[0].co.z += 0.5
    cube.vertices[5].co.x -= 0.4
    bpy.ops.mesh.primitive_cylinder_add(vertices=7)              # 7 quads, two 7-gons
    with_ngons = bpy.context.active_object.data
    for mesh in (triangles_only, mixed, cube):
        loops = triangle_loops(mesh)
        side_edge = triangle_side_edges(mesh, loops, triangle_polygons(mesh, len(loops)))
        corner = loop_vertices(mesh)[loops]
        ends = np.sort(np.stack([corner.ravel(), np.roll(corner, -1, axis=1).ravel()], axis=1), axis=1)
        assert side_edge.shape == loops.shape and side_edge.dtype == np.int32
        pairs = len(np.unique(ends, axis=0))
        assert len(np.unique(side_edge)) == pairs
        assert len(np.unique(np.column_stack([side_edge.ravel(), ends]), axis=0)) == pairs
        diagonals = side_edge >= len(mesh.edges)
        assert diagonals.any() != (mesh is triangles_only)
    loops = triangle_loops(with_ngons)
    assert triangle_side_edges(with_ngons, loops, triangle_polygons(with_ngons, len(loops))) is None
