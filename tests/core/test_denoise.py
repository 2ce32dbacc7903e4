"""The texel-space denoiser does not blur across a contact shadow or a crease (synthetic AO)."""

import numpy as np

import meshes
from seamless_ao.core.image.denoise import denoise


def synthetic(mesh_positions, triangles, truth, rays, seed=0):
    """A layout of a mesh, per-texel values = truth(point) + binomial-like noise for ``rays`` rays."""
    from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
    from seamless_ao.core.layout import build_layout
    from seamless_ao.core.atlas.raster import texel_geometry
    mesh = TriangleMesh.from_triangles(mesh_positions, triangles)
    layout = build_layout(mesh, image_size=256)
    points, _, _ = texel_geometry(layout.texels, layout.atlas, mesh)
    exact = truth(points)
    rng = np.random.default_rng(seed)
    noisy = np.clip(rng.binomial(rays, exact) / rays, 0.0, 1.0)
    return layout, points, exact, noisy


def step_error(layout, points, exact, noisy, rays, band):
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


def test_a_crease_alone_stops_the_blur():
    """Issue 18, item 5: the normal weight by itself.  The AO steps by 0.1 across the line x = 0, under
    two noise sigmas at 64 rays, so the value weight lets it blend; on a flat sheet the filter pulls
    the low side up near the line, with a 40-degree crease there it must pull far less."""
    xs = np.linspace(-1.0, 1.0, 41)
    truth = lambda p: np.where(p[:, 0] < 0.0, 0.5, 0.6)  # noqa: E731
    bias = {}
    for crease in (0.0, 20.0):
        grid = np.array([(x, y, abs(x) * np.tan(np.radians(crease))) for y in xs for x in xs])
        pulled = []
        for seed in range(4):
            layout, points, exact, noisy = synthetic(grid, meshes.grid_triangles(41, 41), truth, rays=64, seed=seed)
            filtered = denoise(layout.texels, layout.atlas, layout.mesh, noisy,
                               np.ones(len(layout.texels), dtype=bool), 64)
            low_side = (points[:, 0] < 0.0) & (points[:, 0] > -1.0 / layout.atlas.density)
            pulled.append((filtered - exact)[low_side].mean())
        bias[crease] = np.mean(pulled)
    assert bias[0.0] > 0.01, bias                       # flat: the step is blurred (the test can see a leak)
    assert bias[20.0] < 0.3 * bias[0.0], bias           # creased: (cos 40°)^16 = 0.014 of the weight crosses


def test_the_weight_widens_as_the_rays_get_fewer():
    """One ray leaves the most noise and gets the widest weight; from 8 rays on it is one texel in a 5x5 window,
    and the window never grows past MAX_RADIUS."""
    from seamless_ao.core.image.denoise import MAX_RADIUS, space_sigma_for, window_radius
    widths = [space_sigma_for(rays) for rays in (1, 2, 4, 8, 64)]
    assert widths == sorted(widths, reverse=True) and widths[0] > 2.5, widths
    assert widths[3] == widths[4] == 1.0 and window_radius(1.0) == 2
    assert all(2 <= window_radius(width) <= MAX_RADIUS for width in widths)
    assert space_sigma_for(0) == space_sigma_for(1)          # a texel with no ray counts as one


def test_a_smooth_field_of_few_rays_comes_out_closer_with_the_wider_weight():
    """AO that changes slowly over a sheet, 2 rays per texel: the default (widened) filter lands nearer the
    truth than the one-texel weight did, and at 8 rays the two are the same filter."""
    xs = np.linspace(-1.0, 1.0, 41)
    grid = np.array([(x, y, 0.0) for y in xs for x in xs])
    truth = lambda p: 0.5 + 0.3 * np.sin(1.5 * p[:, 0]) * np.cos(1.5 * p[:, 1])  # noqa: E731
    layout, points, exact, noisy = synthetic(grid, meshes.grid_triangles(41, 41), truth, rays=2)
    computed = np.ones(len(layout.texels), dtype=bool)
    error = {}
    for name, kwargs in (("fixed", dict(radius=2, space_sigma=1.0)), ("default", {})):
        filtered = denoise(layout.texels, layout.atlas, layout.mesh, noisy, computed, 2, **kwargs)
        error[name] = np.sqrt(np.mean((filtered - exact) ** 2))
    assert error["default"] < 0.8 * error["fixed"], error
    layout, points, exact, noisy = synthetic(grid, meshes.grid_triangles(41, 41), truth, rays=8)
    np.testing.assert_array_equal(
        denoise(layout.texels, layout.atlas, layout.mesh, noisy, computed, np.full(len(noisy), 8)),
        denoise(layout.texels, layout.atlas, layout.mesh, noisy, computed, 8, radius=2, space_sigma=1.0))
