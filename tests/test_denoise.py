"""The texel-space denoiser helps, and does not blur across a contact shadow or a crease."""

import bpy
import numpy as np
import pytest

import meshes
from accuracy import errors, reference_ao, shown_seamless, surface_samples
from blender_scenes import add_object, mesh_from_arrays, sphere_over_plane
from conftest import seamless_ao
from seamless_ao.operators.mesh_data import read_triangles


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
    (sphere_over_plane, lambda p: (p[:, 2] < 0.01) & (np.hypot(p[:, 0], p[:, 1]) < 0.6)),    # contact shadow
    (valley, lambda p: np.abs(p[:, 0]) < 0.08),                                                # the crease
], ids=["contact-shadow", "crease"])
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


def synthetic(mesh_positions, triangles, truth, rays, seed=0):
    """A layout of a mesh, per-texel values = truth(point) + binomial-like noise for ``rays`` rays."""
    from seamless_ao.core.mesh import TriangleMesh
    from seamless_ao.core.pipeline import build_layout
    from seamless_ao.core.raster import texel_geometry
    mesh = TriangleMesh.from_triangles(mesh_positions, triangles)
    layout = build_layout(mesh, image_size=256)
    points, _, _ = texel_geometry(layout.texels, layout.atlas, mesh)
    exact = truth(points)
    rng = np.random.default_rng(seed)
    noisy = np.clip(rng.binomial(rays, exact) / rays, 0.0, 1.0)
    return layout, points, exact, noisy


def step_error(layout, points, exact, noisy, rays, band):
    from seamless_ao.core.denoise import denoise
    computed = np.ones(len(layout.texels), dtype=bool)
    filtered = denoise(layout.texels, layout.atlas, layout.mesh, noisy, computed, rays)
    near_edge = band(points)
    return (np.abs(filtered - exact)[near_edge].mean(), np.abs(noisy - exact)[near_edge].mean(),
            np.abs(filtered - exact)[~near_edge].mean(), np.abs(noisy - exact)[~near_edge].mean())


def test_no_blur_across_a_crease():
    """Across a 40-degree crease inside one chart the AO steps from 0.3 to 0.9: it must stay a step."""
    xs = np.linspace(-1.0, 1.0, 41)
    grid = np.array([(x, y, abs(x) * np.tan(np.radians(20.0))) for y in xs for x in xs])
    triangles = meshes.grid_triangles(41, 41)
    truth = lambda p: np.where(p[:, 0] < 0.0, 0.3, 0.9)  # noqa: E731
    layout, points, exact, noisy = synthetic(grid, triangles, truth, rays=64)
    edge, edge_noisy, rest, rest_noisy = step_error(layout, points, exact, noisy, 64,
                                                    lambda p: np.abs(p[:, 0]) < 3.0 / layout.atlas.density)
    assert rest < 0.6 * rest_noisy            # noise goes down away from the crease
    assert edge < 0.8 * edge_noisy, (edge, edge_noisy)   # and at the crease too: nothing leaks across


def test_no_blur_across_a_contact_shadow_edge():
    """On a flat floor the AO steps from 0.05 (under a plate) to 0.8: the range weight keeps the step."""
    xs = np.linspace(-1.0, 1.0, 41)
    grid = np.array([(x, y, 0.0) for y in xs for x in xs])
    triangles = meshes.grid_triangles(41, 41)
    truth = lambda p: np.where(p[:, 0] < 0.13, 0.05, 0.8)  # noqa: E731
    layout, points, exact, noisy = synthetic(grid, triangles, truth, rays=64)
    edge, edge_noisy, rest, rest_noisy = step_error(layout, points, exact, noisy, 64,
                                                    lambda p: np.abs(p[:, 0] - 0.13) < 3.0 / layout.atlas.density)
    assert rest < 0.6 * rest_noisy
    assert edge < 0.8 * edge_noisy, (edge, edge_noisy)
