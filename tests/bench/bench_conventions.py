"""Benchmark: Rays below the face: three conventions on a coarse smooth mesh.

    .venv/5.0/bin/python tests/bench/bench_conventions.py [--rays 4096] [--points 400]

On a coarse mesh shaded smooth (Suzanne with no subdivision, 500 faces),
the interpolated normal leans far from the face near sharp vertices, so part
of a cosine lobe around it points below the face.  Three ways to treat those
rays, all evaluated at the same visible surface points with many rays:

* the plain reference (tests/support/plain_reference.py): cast them as they are;
* Seamless AO's estimator at the point itself (no texture), with and
  without its mirroring of such rays back above the face;
* Cycles' "Bake > Ambient Occlusion" at 1024² and 256 samples, looked up
  at the points (its texture error is small on so coarse a mesh: the flat-
  shaded row shows how small).

Prints the RMSE between every pair, for the smooth and the flat-shaded mesh
(flat, no normal leans, so the conventions must agree).
"""

import argparse
import sys

from common import finish, markdown_table, say

import bpy
import numpy as np

from accuracy import reference_ao, shown_single_uv, surface_samples  # noqa: E402
from blender_scenes import suzanne  # noqa: E402
from cycles_baseline import UV_NAME, cycles_ao_bake, half_diagonal  # noqa: E402
from seamless_ao.core.rays import ao as ao_module  # noqa: E402
from seamless_ao.core.rays.sampling import cone_directions, tangent_frames  # noqa: E402
from seamless_ao.core.settings import BakeSettings  # noqa: E402
from seamless_ao.core.rays.ray_setup import ray_part  # noqa: E402
from seamless_ao.operators.adapters.casters import caster_maker  # noqa: E402
from seamless_ao.operators.adapters.mesh_data import read_triangles  # noqa: E402

PACKAGE = sys.modules["seamless_ao"]


def estimator_at_points(ob, mesh, triangle, bary, normals, rays, mirror):
    """Seamless AO's own estimator at surface points (no atlas, no texture), rays mirrored or not."""
    settings = BakeSettings(quality="CUSTOM", rays=rays, adaptive=False)
    part = ray_part(mesh, np.array(ob.matrix_world), settings, caster_maker(settings))
    params, caster, to_ray = part.params, part.caster, part.to_ray
    original = ao_module.ray_directions

    def unmirrored(normals, geometric, texel_ids, ray_indices, params, samples=ao_module.texel_samples):
        local = cone_directions(samples(texel_ids, ray_indices, params.seed), params.cone_angle,
                                params.distribution)
        tangent, bitangent = tangent_frames(normals)
        directions = (local[..., 0:1] * tangent[:, None, :] + local[..., 1:2] * bitangent[:, None, :]
                      + local[..., 2:3] * normals[:, None, :])
        return directions, local[..., 2]
    if not mirror:
        ao_module.ray_directions = unmirrored
    try:
        points = np.einsum("kc,kcd->kd", bary, mesh.positions[mesh.triangles[triangle]])
        ray_points, ray_normals = to_ray(points, normals)
        _, geometric = to_ray(points, mesh.triangle_normal[triangle])
        out = np.empty(len(points))
        for start in range(0, len(points), 64):
            part = slice(start, start + 64)
            out[part] = 1.0 - ao_module.occlusion_sums(
                ray_points[part], ray_normals[part], geometric[part], np.arange(len(points))[part],
                np.arange(rays), params, caster)[0] / rays
        return out
    finally:
        ao_module.ray_directions = original
        caster.free()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=4096)
    parser.add_argument("--points", type=int, default=400)
    args = parser.parse_args()
    rows = []
    for smooth in (True, False):
        if hasattr(bpy.types.Scene, "seamless_ao"):
            PACKAGE.unregister()
        bpy.ops.wm.read_factory_settings(use_empty=True)
        PACKAGE.register()
        ob = suzanne(0, name="Coarse Suzanne", smooth=smooth)
        bpy.context.view_layer.update()
        mesh, loops = read_triangles(ob.data)
        triangle, bary, normals = surface_samples(mesh, args.points, seed=6)
        values = {"plain reference": reference_ao(ob, mesh, triangle, bary, normals, rays=args.rays, seed=2)}
        values["Seamless AO, mirrored (now)"] = estimator_at_points(ob, mesh, triangle, bary, normals, args.rays, True)
        values["Seamless AO, cast as they are"] = estimator_at_points(ob, mesh, triangle, bary, normals, args.rays,
                                                                      False)
        distance = half_diagonal(ob, mesh)
        image, _, _ = cycles_ao_bake(ob, 1024, 256, distance)
        values["Cycles bake 1024², 256"] = shown_single_uv(ob, image, UV_NAME, loops, triangle, bary)
        names = list(values)
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                difference = values[a] - values[b]
                rows.append(["smooth" if smooth else "flat", a, b, "{:.4f}".format(np.sqrt(np.mean(difference**2))),
                             "{:+.4f}".format(np.mean(difference))])
        print(markdown_table(["shading", "A", "B", "RMSE A-B", "mean A-B"], rows[-len(names) * (len(names) - 1) // 2:]),
              flush=True)
    say()
    say(markdown_table(["shading", "A", "B", "RMSE A-B", "mean A-B"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
