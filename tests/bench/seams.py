"""Seams as the report measures them: point pairs a tiny step either side of each chart border (Seamless AO)
or UV island border (Cycles), how much the shown AO jumps across them beyond the reference's own jump, and
close-up renders of the worst Cycles border."""

import numpy as np

import bpy
import package
from accuracy import shown_single_uv
from cycles_baseline import UV_NAME
from plain_reference import hidden
from seamless_ao.operators.adapters.mesh_data import read_triangles

PACKAGE = package.seamless_ao
#: Chart borders sampled per mesh (three point pairs each).
SEAM_EDGES = 150


def seam_pairs(mesh, loops, uv_layers, rng, limit=SEAM_EDGES, step=1e-4):
    """Point pairs either side of UV seams: ``(tri_a, bary_a, tri_b, bary_b)``.

    An edge is a seam when the two triangles sharing it map it to different
    UVs in any of ``uv_layers`` (each (loops, 2)).
    """
    from seamless_ao.core.mesh.adjacency import face_adjacency
    topology = face_adjacency(mesh)
    welded = topology.welded_triangles
    sides = []
    for k in range(3):
        a, b = welded[:, k], welded[:, (k + 1) % 3]
        sides.append(np.stack([np.minimum(a, b), np.maximum(a, b), np.arange(len(welded)), np.full(len(welded), k)], 1))
    sides = np.concatenate(sides)
    sides = sides[sides[:, 0] != sides[:, 1]]
    order = np.lexsort((sides[:, 1], sides[:, 0]))
    sides = sides[order]
    same = (sides[1:, 0] == sides[:-1, 0]) & (sides[1:, 1] == sides[:-1, 1])
    first, second = sides[:-1][same], sides[1:][same]
    seams = np.zeros(len(first), dtype=bool)
    for uv in uv_layers:
        for f, s in ((first, second),):
            fa = uv[loops[f[:, 2], f[:, 3]]]
            fb = uv[loops[f[:, 2], (f[:, 3] + 1) % 3]]
            # the same welded vertex in the other triangle
            s_verts = welded[s[:, 2]]
            s_loops = loops[s[:, 2]]
            match_a = np.argmax(s_verts == welded[f[:, 2], f[:, 3]][:, None], axis=1)
            match_b = np.argmax(s_verts == welded[f[:, 2], (f[:, 3] + 1) % 3][:, None], axis=1)
            sa = uv[s_loops[np.arange(len(s)), match_a]]
            sb = uv[s_loops[np.arange(len(s)), match_b]]
            seams |= (np.abs(fa - sa).max(1) > 1e-6) | (np.abs(fb - sb).max(1) > 1e-6)
    skip = mesh.degenerate
    index = np.flatnonzero(seams & ~skip[first[:, 2]] & ~skip[second[:, 2]])
    if len(index) > limit:
        index = rng.choice(index, size=limit, replace=False)
    pairs = []
    for i in index:
        ta, ka = first[i, 2], first[i, 3]
        tb = second[i, 2]
        for t in (0.25, 0.5, 0.75):
            edge_bary = np.zeros(3)
            edge_bary[ka], edge_bary[(ka + 1) % 3] = 1 - t, t
            point = edge_bary @ mesh.positions[mesh.triangles[ta]]
            bary_a = _nudge(mesh, ta, point, step)
            bary_b = _nudge(mesh, tb, point, step)
            pairs.append((ta, bary_a, tb, bary_b))
    # seam points lying on an opposite-facing surface are never seen (see accuracy.surface_samples)
    if pairs:
        ta, ba, tb, bb = (np.array(column) for column in zip(*pairs))
        on_a = np.einsum("kc,kcd->kd", ba, mesh.positions[mesh.triangles[ta]])
        on_b = np.einsum("kc,kcd->kd", bb, mesh.positions[mesh.triangles[tb]])
        sides = hidden(mesh.positions, mesh.triangles, np.concatenate([ta, tb]), np.vstack([on_a, on_b]))
        seen = ~(sides[:len(ta)] | sides[len(ta):])
        pairs = [pair for pair, keep in zip(pairs, seen) if keep]
    if not pairs:
        return None
    ta, ba, tb, bb = zip(*pairs)
    return np.array(ta), np.array(ba), np.array(tb), np.array(bb)


def _nudge(mesh, triangle, point, step):
    """Barycentrics of ``point`` moved ``step`` (relative to mesh size) toward the triangle's centre."""
    corners = mesh.positions[mesh.triangles[triangle]]
    centre = corners.mean(axis=0)
    direction = centre - point
    length = np.linalg.norm(direction)
    moved = point + direction / max(length, 1e-300) * min(step * mesh.scale, 0.5 * length)
    matrix = np.column_stack([corners[1] - corners[0], corners[2] - corners[0]])
    solution, *_ = np.linalg.lstsq(matrix, moved - corners[0], rcond=None)
    return np.array([1 - solution.sum(), solution[0], solution[1]])


def seam_error(show, ref_a, ref_b, pairs):
    """Mean and 99th percentile of |jump shown - jump in the reference| across seams."""
    ta, ba, tb, bb = pairs
    jump = np.abs((show(ta, ba) - show(tb, bb)) - (ref_a - ref_b))
    return float(jump.mean()), float(np.percentile(jump, 99))


def point_normals(mesh, triangle, bary):
    normals = np.einsum("kc,kcd->kd", bary, mesh.corner_normals[triangle])
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def seam_renders(ob, out, image):
    """Close-ups of the Cycles UV island border that jumps most, shaded by each method's AO (emission).

    ``image`` is the Cycles bake (through ``CyclesAO``); the object's current Seamless AO bake is the other.
    """
    from blender_checks import uv_layer_array
    scene = bpy.context.scene
    mesh, loops = read_triangles(ob.data)
    pairs = seam_pairs(mesh, loops, [uv_layer_array(ob.data, UV_NAME)], np.random.default_rng(2), limit=2000)
    ta, ba, tb, bb = pairs
    jump = np.abs(shown_single_uv(ob, image, UV_NAME, loops, ta, ba) - shown_single_uv(ob, image, UV_NAME, loops, tb, bb))
    worst = int(np.argmax(jump))
    matrix = np.array(ob.matrix_world)
    point = ba[worst] @ mesh.positions[mesh.triangles[ta[worst]]]
    normal = point_normals(mesh, ta[worst:worst + 1], ba[worst:worst + 1])[0]
    world_point = matrix[:3, :3] @ point + matrix[:3, 3]
    world_normal = matrix[:3, :3] @ normal
    world_normal /= np.linalg.norm(world_normal)
    from mathutils import Vector
    camera = bpy.data.objects.new("Seam Camera", bpy.data.cameras.new("Seam Camera"))
    scene.collection.objects.link(camera)
    camera.location = Vector(world_point + world_normal * 0.18 * mesh.scale)
    camera.rotation_euler = Vector(-world_normal).to_track_quat("-Z", "Y").to_euler()
    camera.data.lens = 50.0
    camera.data.clip_start = 0.001
    scene.camera = camera
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 16
    scene.render.resolution_x = scene.render.resolution_y = 400
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    paths = []
    for label in ("seamless", "cycles"):
        tree = ob.active_material.node_tree
        if label == "seamless":
            PACKAGE.set_preview([ob], True)
        else:
            PACKAGE.set_preview([ob], False)
            texture = tree.nodes.new("ShaderNodeTexImage")
            texture.image = image
            uv = tree.nodes.new("ShaderNodeUVMap")
            uv.uv_map = UV_NAME
            tree.links.new(uv.outputs["UV"], texture.inputs["Vector"])
            emission = tree.nodes.new("ShaderNodeEmission")
            tree.links.new(texture.outputs["Color"], emission.inputs["Color"])
            output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
            tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
        path = out / "seam_{}.png".format(label)
        scene.render.filepath = str(path)
        bpy.ops.render.render(write_still=True)
        paths.append(path)
    from PIL import Image
    left, right = (Image.open(p) for p in paths)
    both = Image.new("RGB", (left.width + right.width, left.height))
    both.paste(left, (0, 0))
    both.paste(right, (left.width, 0))
    both.save(out / "seam_side_by_side.png")
    for path in paths:                     # the two halves are in the side-by-side image
        path.unlink()
    print("  wrote seam close-ups (left Seamless AO, right Cycles) to", out / "seam_side_by_side.png")
