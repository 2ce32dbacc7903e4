"""Would Cycles cast our rays faster? Cycles' AO at our own texels against the Geometry Nodes caster

Issue 30 asks whether Cycles (Embree) should be an optional ray engine, if it is faster at equal error.
Cycles has no call that casts given rays, so the one route is a bake: a mesh of one tiny triangle per
texel (the texel's lifted surface point, its shading normal as a custom normal, a UV triangle around
the texel's centre and no other), invisible to every ray kind, baked with "Bake > Ambient Occlusion"
into an image of the atlas' size while the object itself stays in the scene as the occluder. Cycles
is set to what AO needs (no bounces, no adaptive sampling, no denoising, the same maximum distance);
its settings are put back afterwards.

Both routes shade the same texels of one Seamless AO layout at 256² with the same number of rays per
texel, without adaptive stopping, weighted rays or denoising. Time: Seamless AO's rays stage (as the
bake reports it, BVH build and crease pass included) against the whole bake call (scene sync and BVH
build included; building the texel mesh is not counted), median of the runs. Error: at random covered
texels that no piece buries, against the plain reference (tests/support/plain_reference.py, mathutils'
BVH, no code shared with either route) at the same points and normals.
"""

import argparse
import time

import numpy as np

from common import finish, markdown_table, say

import bpy
from bench_fixed_cost import scene
from plain_reference import hidden, plain_ao
from seamless_ao.core.mesh import mesh_size
from seamless_ao.core.pipeline import bake_arrays
from seamless_ao.core.raster import COVERED, texel_geometry
from seamless_ao.core.rays import ORIGIN_OFFSET
from seamless_ao.operators.adapters.casters import NodesCaster
from seamless_ao.operators.adapters.mesh_data import read_triangles

#: Half-size of each texel's triangle in 3D, relative to the object's diagonal (far below a texel).
TEXEL_TRIANGLE = 1e-4
#: Ray kinds the texel mesh is hidden from (it must never occlude).
RAY_VISIBILITY = ("visible_diffuse", "visible_glossy", "visible_transmission", "visible_volume_scatter",
                  "visible_shadow")


def texel_mesh(points, shading, geometric, xy, width, height, diagonal):
    """A mesh of one small triangle per texel: at the point lifted along ``geometric`` by our rays' offset, facing it,
    smooth shaded with ``shading`` as its normals, its UV triangle around the texel's centre."""
    count = len(points)
    lifted = points + geometric * (ORIGIN_OFFSET * diagonal)
    helper = np.where(np.abs(geometric[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    first = np.cross(geometric, helper)
    first /= np.linalg.norm(first, axis=1)[:, None]
    second = np.cross(geometric, first)
    size = TEXEL_TRIANGLE * diagonal
    corners = np.stack([lifted - size * (first + 0.5 * second), lifted + size * (first - 0.5 * second),
                        lifted + size * second], axis=1)
    centre = xy.astype(np.float64) + 0.5
    uv = np.stack([centre + [-0.45, -0.3], centre + [0.45, -0.3], centre + [0.0, 0.45]], axis=1)
    uv /= np.array([width, height], dtype=np.float64)
    mesh = bpy.data.meshes.new("bench texels")
    mesh.vertices.add(3 * count)
    mesh.vertices.foreach_set("co", corners.astype(np.float32).ravel())
    mesh.loops.add(3 * count)
    mesh.loops.foreach_set("vertex_index", np.arange(3 * count, dtype=np.int32))
    mesh.polygons.add(count)
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * count, 3, dtype=np.int32))
    mesh.uv_layers.new(name="texels").data.foreach_set("uv", uv.astype(np.float32).ravel())
    mesh.update()
    mesh.polygons.foreach_set("use_smooth", np.ones(count, dtype=bool))
    mesh.normals_split_custom_set_from_vertices(np.repeat(shading, 3, axis=0).astype(np.float32))
    return mesh


def cycles_texel_ao(points, shading, geometric, xy, width, height, samples, diagonal, runs):
    """Cycles' AO at the texels, rays reaching half the object's ``diagonal``: (values (k,), median seconds
    of the bake call)."""
    context = bpy.context
    scene_data = context.scene
    max_distance = 0.5 * diagonal
    mesh = texel_mesh(points, shading, geometric, xy, width, height, diagonal)
    ob = bpy.data.objects.new("bench texels", mesh)
    scene_data.collection.objects.link(ob)
    for name in RAY_VISIBILITY:
        setattr(ob, name, False)
    image = bpy.data.images.new("bench texels", width, height, alpha=False, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    material = bpy.data.materials.new("bench texels")
    material.use_nodes = True
    node = material.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    material.node_tree.nodes.active = node
    mesh.materials.append(material)
    cycles = scene_data.cycles
    kept = {name: getattr(cycles, name) for name in ("samples", "use_denoising", "use_adaptive_sampling",
                                                     "max_bounces", "diffuse_bounces", "device")}
    kept_engine = scene_data.render.engine
    if scene_data.world is None:
        scene_data.world = bpy.data.worlds.new("bench world")
    kept_distance = scene_data.world.light_settings.distance
    try:
        scene_data.render.engine = "CYCLES"
        cycles.device, cycles.samples, cycles.use_denoising = "CPU", samples, False
        cycles.use_adaptive_sampling, cycles.max_bounces, cycles.diffuse_bounces = False, 0, 0
        scene_data.world.light_settings.distance = max_distance
        context.view_layer.update()
        for other in context.view_layer.objects:
            other.select_set(other is ob)
        context.view_layer.objects.active = ob
        seconds = []
        for _ in range(runs):
            start = time.perf_counter()
            bpy.ops.object.bake(type="AO", margin=0, use_clear=True)
            seconds.append(time.perf_counter() - start)
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        flat = xy[:, 1] * width + xy[:, 0]
        return pixels.reshape(-1, 4)[flat, 0].astype(np.float64), float(np.median(seconds))
    finally:
        for name, value in kept.items():
            setattr(cycles, name, value)
        scene_data.render.engine = kept_engine
        scene_data.world.light_settings.distance = kept_distance
        bpy.data.objects.remove(ob)
        bpy.data.meshes.remove(mesh)
        bpy.data.materials.remove(material)
        bpy.data.images.remove(image)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--rays", type=int, nargs="+", default=[16, 64])
    parser.add_argument("--points", type=int, default=600, help="texels the reference is computed at")
    parser.add_argument("--reference-rays", type=int, default=2048)
    args = parser.parse_args()
    rows = []
    for name in ("Suzanne", "scan", "interior"):
        ob = scene(name)
        mesh, _ = read_triangles(ob.data)
        diagonal = mesh_size(mesh.positions)
        reference = None
        for rays in args.rays:
            ours, seconds = [], []
            for _ in range(args.runs):
                result = bake_arrays(mesh, make_caster=NodesCaster, image_size=args.size, rays=rays, adaptive=False,
                                     weighted_rays=False, denoise=False)
                seconds.append(result.timings["rays"])
            layout = result.layout
            texels = layout.texels
            cast = np.flatnonzero(result.computed)
            points, shading, geometric = texel_geometry(texels, layout.atlas, layout.mesh, cast)
            if reference is None:
                # the texels are the same at every ray count (the layout does not depend on it)
                # covered texels at points a viewer can see: a texel whose own point lies inside another
                # piece is shaded at the crease instead (core/job.py), which the reference cannot know
                judged = np.flatnonzero((texels.kind[cast] == COVERED) & ~result.buried[cast])
                judged = np.random.default_rng(7).choice(judged, min(2 * args.points, len(judged)), replace=False)
                triangle = layout.atlas.member_triangle[texels.member[cast[judged]]]
                seen = ~hidden(mesh.positions, mesh.triangles, triangle, points[judged])
                judged = np.sort(judged[seen][:args.points])
                reference = plain_ao(mesh.positions, mesh.triangles, points[judged], shading[judged],
                                     geometric[judged], 0.5 * diagonal, rays=args.reference_rays)
                reference_noise = float(np.sqrt(np.mean(reference * (1 - reference)) / args.reference_rays))
            ours_error = result.texel_ao[cast][judged] - reference
            rows.append([name, "Seamless AO, Geometry Nodes", rays, "{:,}".format(len(cast)),
                         "{:.2f}".format(np.median(seconds)),
                         "{:.2f}".format(result.rays / np.median(seconds) / 1e6),
                         "{:.4f}".format(np.sqrt(np.mean(ours_error ** 2))), "{:+.4f}".format(ours_error.mean()), ""])
            print(rows[-1], flush=True)
            values, bake_seconds = cycles_texel_ao(points, shading, geometric, texels.xy(cast), texels.width,
                                                   texels.height, rays, diagonal, args.runs)
            cycles_error = values[judged] - reference
            rows.append([name, "Cycles at the same texels", rays, "{:,}".format(len(cast)),
                         "{:.2f}".format(bake_seconds), "{:.2f}".format(len(cast) * rays / bake_seconds / 1e6),
                         "{:.4f}".format(np.sqrt(np.mean(cycles_error ** 2))),
                         "{:+.4f}".format(cycles_error.mean()), "{:.1f}".format(np.median(seconds) / bake_seconds)])
            print(rows[-1], "reference noise", reference_noise, flush=True)
    say("At {}², median of {} runs; error at {} covered texels per mesh against {} reference rays each "
        "(the reference's own noise is about {:.3f} RMS on the last mesh).".format(
            args.size, args.runs, args.points, args.reference_rays, reference_noise))
    say()
    say(markdown_table(["mesh", "route", "rays per texel", "texels", "seconds", "M rays/s", "RMSE", "mean error",
                        "Cycles' speed-up"],
                       rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
