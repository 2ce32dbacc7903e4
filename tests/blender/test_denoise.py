"""The denoiser on real bakes: lower error, edges kept."""

import bpy
import numpy as np
import pytest

import meshes
from accuracy import errors, reference_ao, shown_seamless, surface_samples
from blender_scenes import add_object, mesh_from_arrays, sphere_over_plane
from marks import heavy
from package import seamless_ao
from seamless_ao.operators.adapters.mesh_data import read_triangles


def valley():
    """Two slopes meeting in a 140-degree valley (both in the +Z chart), with some width."""
    positions, triangles = [], []
    xs = np.linspace(-1.0, 1.0, 41)
    ys = np.linspace(-1.0, 1.0, 41)
    for y in ys:
        for x in xs:
            positions.append((x, y, abs(x) * np.tan(np.radians(20.0))))
    triangles = meshes.grid_triangles(len(ys), len(xs))
    return add_object("Valley", mesh_from_arrays("Valley", np.array(positions), triangles))


def near(mesh, triangle, bary, test):
    points = np.einsum("kc,kcd->kd", bary, mesh.positions[mesh.triangles[triangle]])
    return test(points)


@pytest.mark.parametrize("scene, region", [
    pytest.param(sphere_over_plane, lambda p: (p[:, 2] < 0.01) & (np.hypot(p[:, 0], p[:, 1]) < 0.6),
                 id="contact-shadow"),
    pytest.param(valley, lambda p: np.abs(p[:, 0]) < 0.08, marks=heavy, id="crease"),
])
def test_denoising_lowers_error_and_keeps_edges(scene, region, fresh_scene, addon):
    ob = scene()
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals = surface_samples(mesh, 4000, seed=4)
    keep = near(mesh, triangle, bary, region)
    triangle, bary, normals = triangle[keep], bary[keep], normals[keep]
    assert len(triangle) > 150
    reference = reference_ao(ob, mesh, triangle, bary, normals, rays=1024)
    result = {}
    for flag in (False, True):
        report = seamless_ao.bake([ob], image_size=512, rays=16, denoise=flag)
        shown = shown_seamless(ob, bpy.data.images[report.image], loops, triangle, bary, normals)
        result[flag] = errors(shown, reference)
    # noise goes down; a blur across the edge would raise the error at the edge instead
    assert result[True][0] < 0.85 * result[False][0], result
    assert result[True][1] <= result[False][1] + 0.01, result
