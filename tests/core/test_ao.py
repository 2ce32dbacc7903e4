"""Issue 9: AO ray casting, against closed-form answers."""

import numpy as np
import pytest

from seamless_ao.core.rays.ao import MIN_SIDE_TRIPLES, noise_estimate, occlusion_sums
from seamless_ao.core.rays.job import point_ao
from seamless_ao.core.rays.ray_setup import AOParams, BVHCaster
from seamless_ao.core.rays.sampling import cone_directions, random_samples, sobol_2d, texel_samples

BIG = 1000.0


def shade(points, normals, geometric, ids, params, caster, samples=None):
    """AO of points as a bake computes it (:func:`point_ao`: pilot rays, the adaptive stop, the rest), or,
    with other ``samples`` than the bake's (to compare sequences), every ray of those samples."""
    if samples is None:
        return point_ao(points, normals, geometric, params, caster, ids)
    sums = occlusion_sums(points, normals, geometric, ids, np.arange(params.rays), params, caster, samples)[0]
    return np.clip(1.0 - sums / params.rays, 0.0, 1.0).astype(np.float32), len(points) * params.rays


def quads(*quads_):
    """Triangles of some quads, each given as 4 corners (counter-clockwise seen from the front)."""
    positions = np.array([corner for quad in quads_ for corner in quad], dtype=np.float64)
    triangles = []
    for q in range(len(quads_)):
        a = 4 * q
        triangles += [[a, a + 1, a + 2], [a, a + 2, a + 3]]
    return positions, np.array(triangles)


FLOOR = [(-BIG, -BIG, 0), (BIG, -BIG, 0), (BIG, BIG, 0), (-BIG, BIG, 0)]
WALL_X0 = [(0, -BIG, 0), (0, BIG, 0), (0, BIG, BIG), (0, -BIG, BIG)]        # plane x = 0, facing +X


def floor_points(xs):
    points = np.stack([xs, np.zeros_like(xs), np.zeros_like(xs)], axis=1)
    up = np.tile([0.0, 0.0, 1.0], (len(xs), 1))
    return points, up


def wall_fraction(distance_to_wall, max_distance):
    """Cosine-weighted fraction of the hemisphere that hits a wall within max distance.

    Cosine-distributed directions project to points uniform on the unit disk
    (Malley), so the blocked fraction is the disk segment dx <= -s, s = a / R.
    """
    s = np.clip(distance_to_wall / max_distance, 0.0, 1.0)
    return (np.arccos(s) - s * np.sqrt(1.0 - s * s)) / np.pi


def test_open_plane_is_fully_open():
    caster = BVHCaster(*quads(FLOOR))
    points, up = floor_points(np.linspace(-5, 5, 50))
    ao, _ = shade(points, up, up, np.arange(50), AOParams(rays=64, max_distance=10.0), caster)
    assert (ao == 1.0).all()


def test_floor_at_the_foot_of_a_wall_is_half_occluded():
    caster = BVHCaster(*quads(FLOOR, WALL_X0))
    points, up = floor_points(np.full(200, 1e-9))
    params = AOParams(rays=256, max_distance=1e6, adaptive=False)
    ao, _ = shade(points, up, up, np.arange(200), params, caster)
    assert abs(ao.mean() - 0.5) < 0.01
    assert np.abs(ao - 0.5).max() < 0.03


@pytest.mark.parametrize("distribution", ["COSINE"])
def test_floor_near_a_wall_with_finite_distance_matches_closed_form(distribution):
    caster = BVHCaster(*quads(FLOOR, WALL_X0))
    distances = np.linspace(0.0, 3.0, 120)
    points, up = floor_points(distances + 1e-9)
    params = AOParams(rays=512, max_distance=2.5, adaptive=False, distribution=distribution)
    ao, _ = shade(points, up, up, np.arange(len(points)), params, caster)
    exact = 1.0 - wall_fraction(distances, 2.5)
    assert np.sqrt(np.mean((ao - exact) ** 2)) < 0.01
    assert np.abs(ao - exact).max() < 0.04
    assert (ao[distances >= 2.5] == 1.0).all()


def test_floor_of_a_closed_box_is_fully_occluded():
    from meshes import box
    positions, triangles = box(size=(2.0, 2.0, 2.0), subdivisions=2)
    caster = BVHCaster(positions, triangles[:, ::-1])             # faces pointing inward
    xs = np.linspace(-0.9, 0.9, 30)
    points = np.stack([xs, xs[::-1] * 0.5, np.full_like(xs, -1.0)], axis=1)
    up = np.tile([0.0, 0.0, 1.0], (30, 1))
    ao, _ = shade(points, up, up, np.arange(30), AOParams(rays=64, max_distance=100.0), caster)
    assert (ao == 0.0).all()


@pytest.mark.parametrize("distribution", ["COSINE", "UNIFORM"])
@pytest.mark.parametrize("cone", [20.0, 45.0])
def test_narrow_cone_under_a_ceiling(distribution, cone):
    """A ceiling at height h; a ray at angle phi hits within R iff cos(phi) >= h / R."""
    height = 1.0
    ceiling = [(-BIG, -BIG, height), (-BIG, BIG, height), (BIG, BIG, height), (BIG, -BIG, height)]
    caster = BVHCaster(*quads(ceiling))
    cos_max = np.cos(np.radians(cone))
    for max_distance in (height / np.cos(np.radians(cone * 0.5)), height / cos_max * 1.01):
        points, up = floor_points(np.linspace(-1, 1, 100))
        params = AOParams(rays=256, max_distance=max_distance, cone_angle=cone, distribution=distribution,
                          adaptive=False)
        ao, _ = shade(points, up, up, np.arange(100), params, caster)
        c = min(height / max_distance, 1.0)
        if distribution == "COSINE":      # cos^2 uniform in [cos_max^2, 1]
            blocked = (1 - c**2) / (1 - cos_max**2) if c >= cos_max else 1.0
        else:                             # cos uniform in [cos_max, 1]
            blocked = (1 - c) / (1 - cos_max) if c >= cos_max else 1.0
        assert abs(ao.mean() - (1 - blocked)) < 0.01, (max_distance, ao.mean(), 1 - blocked)


def test_sobol_prefixes_are_stratified():
    points = sobol_2d(np.arange(64)).astype(np.float64) / 2**32
    for k in (4, 16, 64):
        cells = np.floor(points[:k] * np.sqrt(k)).astype(int)
        assert len({tuple(c) for c in cells}) == k, "the first {} points do not fill a {}-cell grid".format(k, k)


def test_sobol_points_do_not_depend_on_the_batch_they_are_asked_in():
    """Rays 16..23 asked alone (the adaptive pass asks for the rays after the pilot) are rays 16..23, not 0..7."""
    whole = sobol_2d(np.arange(4096))
    for start, stop in ((16, 24), (17, 28), (1024, 1100), (4000, 4096)):
        assert (sobol_2d(np.arange(start, stop)) == whole[start:stop]).all(), (start, stop)


def test_first_4096_sobol_points_are_distinct_and_every_power_of_two_prefix_is_stratified():
    """(0, 2)-sequence: each prefix of 2^k points has one point in every 2^a x 2^(k-a) box, for every a."""
    points = sobol_2d(np.arange(4096))
    assert len({tuple(p) for p in points.tolist()}) == 4096
    for k in range(13):
        prefix = points[:2**k]
        for a in range(k + 1):
            cell = (prefix[:, 0] >> np.uint64(32 - a)) * np.uint64(2**(k - a)) + (prefix[:, 1] >> np.uint64(32 - (k - a)))
            assert len(np.unique(cell)) == 2**k, (k, a)


def test_convergence_and_low_discrepancy_beats_random():
    caster = BVHCaster(*quads(FLOOR, WALL_X0))
    distances = np.linspace(0.0, 2.0, 150)
    points, up = floor_points(distances + 1e-9)
    exact = 1.0 - wall_fraction(distances, 2.5)
    errors = {}
    for rays in (16, 64, 256):
        params = AOParams(rays=rays, max_distance=2.5, adaptive=False, seed=7)
        ao, _ = shade(points, up, up, np.arange(150), params, caster)
        errors[rays] = np.sqrt(np.mean((ao - exact) ** 2))
        random_ao, _ = shade(points, up, up, np.arange(150), params, caster, samples=random_samples)
        errors[rays, "random"] = np.sqrt(np.mean((random_ao - exact) ** 2))
    assert errors[16] > errors[64] > errors[256]
    for rays in (16, 64, 256):
        assert errors[rays] < 0.8 * errors[rays, "random"], errors


def test_same_seed_same_result_bit_for_bit():
    caster = BVHCaster(*quads(FLOOR, WALL_X0))
    points, up = floor_points(np.linspace(0.0, 2.0, 64))
    params = AOParams(rays=32, max_distance=2.0, seed=3)
    first, _ = shade(points, up, up, np.arange(64), params, caster)
    second, _ = shade(points, up, up, np.arange(64), params, caster)
    assert first.tobytes() == second.tobytes()
    other, _ = shade(points, up, up, np.arange(64), AOParams(rays=32, max_distance=2.0, seed=4), caster)
    assert other.tobytes() != first.tobytes()


def test_batching_does_not_change_the_result():
    caster = BVHCaster(*quads(FLOOR, WALL_X0))
    points, up = floor_points(np.linspace(0.0, 2.0, 64))
    params = AOParams(rays=32, max_distance=2.0)
    whole, _ = shade(points, up, up, np.arange(64), params, caster)
    halves = np.concatenate([shade(points[:20], up[:20], up[:20], np.arange(20), params, caster)[0],
                             shade(points[20:], up[20:], up[20:], np.arange(20, 64), params, caster)[0]])
    assert whole.tobytes() == halves.tobytes()


def test_falloff_modes_order():
    caster = BVHCaster(*quads(FLOOR, WALL_X0))
    points, up = floor_points(np.linspace(0.05, 1.0, 40))
    results = {}
    for falloff in ("NONE", "LINEAR", "OBSCURANCE"):
        params = AOParams(rays=128, max_distance=2.0, falloff=falloff, adaptive=False)
        results[falloff] = shade(points, up, up, np.arange(40), params, caster)[0]
    # distance-weighted occlusion is never more than binary occlusion
    assert (results["LINEAR"] >= results["NONE"] - 1e-6).all()
    assert (results["OBSCURANCE"] >= results["NONE"] - 1e-6).all()
    assert (results["LINEAR"] > results["NONE"]).any()


def test_ground_plane_and_backfaces():
    # a single upward-facing square hovering at z = 1; below it a point facing down
    square = [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
    caster = BVHCaster(*quads(square))
    below = np.array([[0.0, 0.0, 0.5]])
    up = np.array([[0.0, 0.0, 1.0]])
    # looking up at the back of the square: occluded unless back faces are ignored
    params = AOParams(rays=256, max_distance=100.0, adaptive=False)
    blocked = shade(below, up, up, np.arange(1), params, caster)[0][0]
    params.ignore_backfaces = True
    through = shade(below, up, up, np.arange(1), params, caster)[0][0]
    assert blocked < 0.5 and through == 1.0
    # the ground plane occludes a point facing down
    down = -up
    params = AOParams(rays=64, max_distance=100.0, ground_height=0.0)
    assert shade(below, down, down, np.arange(1), params, caster)[0][0] == 0.0
    params.ground_height = None
    assert shade(below, down, down, np.arange(1), params, caster)[0][0] == 1.0


def test_coarse_smooth_normal_does_not_darken_wholesale():
    """A shading normal tilted 40 degrees off a flat face must not send rays into it."""
    caster = BVHCaster(*quads(FLOOR))
    points, up = floor_points(np.linspace(-1, 1, 20))
    tilt = np.radians(40.0)
    shading = np.tile([np.sin(tilt), 0.0, np.cos(tilt)], (20, 1))
    ao, _ = shade(points, shading, up, np.arange(20), AOParams(rays=64, max_distance=10.0), caster)
    assert (ao == 1.0).all()


def test_cone_directions_stay_in_the_cone():
    samples = texel_samples(np.arange(10), np.arange(64), 0)
    for cone in (10.0, 45.0, 90.0):
        d = cone_directions(samples, cone)
        assert np.allclose(np.linalg.norm(d, axis=-1), 1.0)
        assert (d[..., 2] >= np.cos(np.radians(cone)) - 1e-12).all()



def test_noise_estimate_matches_independent_rays():
    """For independent binary rays the bound is the actual RMS error, whatever the ray count."""
    rng = np.random.default_rng(4)
    truth = rng.random(40000)
    for rays in (4, 16, 64):
        estimate = rng.binomial(rays, truth) / rays
        actual = np.sqrt(np.mean((estimate - truth) ** 2))
        assert noise_estimate(estimate, rays) == pytest.approx(actual, rel=0.03)
    assert noise_estimate(np.ones(10), 16) == 0.0 and noise_estimate(np.zeros(0), 16) == 0.0
    assert noise_estimate(np.full(10, 0.5), 1) == pytest.approx(0.5)


def test_noise_estimate_with_one_ray_is_not_zero():
    """One binary ray per texel gives 0 or 1, whose own spread is 0: the estimate pools the texels instead,
    never under the actual RMS error and close to it when AO varies as little as across a real bake."""
    rng = np.random.default_rng(5)
    for low, high in ((0.0, 1.0), (0.7, 1.0), (0.85, 0.95)):
        truth = rng.uniform(low, high, 40000)
        estimate = rng.binomial(1, truth).astype(float)
        actual = np.sqrt(np.mean((estimate - truth) ** 2))
        assert actual * 0.98 < noise_estimate(estimate, 1) < actual * (1.25 if low == 0.0 else 1.05)
    mixed = np.r_[rng.binomial(1, np.full(20000, 0.9)), rng.binomial(16, np.full(20000, 0.9)) / 16]
    rays = np.r_[np.ones(20000), np.full(20000, 16)]
    assert noise_estimate(mixed, rays) == pytest.approx(np.sqrt((0.09 + 0.09 / 16) / 2), rel=0.03)


def test_noise_estimate_sees_stratified_rays_through_texels_side_by_side():
    """Stratified rays err less than independent ones. Three texels in a row a, b, c differ by a - 2b + c,
    whose mean square is six times their variance whatever straight gradient the AO has, so the estimate
    follows the actual error; where the AO itself changes from texel to texel that reads high, and each
    texel's own rays give the figure."""
    rng = np.random.default_rng(6)
    rows, width, rays = 400, 100, 16
    neighbour = np.arange(1, rows * width + 1)
    neighbour[width - 1::width] = -1                                   # the last texel of each row
    error = rng.normal(0.0, 0.03, rows * width)                        # about a third of independent rays'
    actual = np.sqrt(np.mean(error**2))
    smooth = np.tile(np.linspace(0.3, 0.9, width), rows) + error       # a gradient along every row
    assert noise_estimate(smooth, rays) > 2.5 * actual
    assert noise_estimate(smooth, rays, neighbour) == pytest.approx(actual, rel=0.05)
    rough = rng.uniform(0.3, 0.9, rows * width) + error                # AO that changes from texel to texel
    assert noise_estimate(rough, rays, neighbour) == noise_estimate(rough, rays)
    few = np.full(rows * width, -1)
    few[:MIN_SIDE_TRIPLES - 1] = np.arange(1, MIN_SIDE_TRIPLES)        # one run, too short to go by
    assert noise_estimate(smooth, rays, few) == noise_estimate(smooth, rays)


CEILING = [(-BIG, -BIG, 1.0), (-BIG, BIG, 1.0), (BIG, BIG, 1.0), (BIG, -BIG, 1.0)]    # z = 1, facing down


@pytest.mark.parametrize("falloff, expected", [
    # cosine rays, cos(theta) = c with density 2c; a hit at d = h / c occludes for c >= a = h / R by
    # 1 (NONE), 1 - d / R = 1 - a / c (LINEAR), 1 - sqrt(d / R) = 1 - sqrt(a / c) (OBSCURANCE)
    ("NONE", lambda a: a**2),
    ("LINEAR", lambda a: 1.0 - (1.0 - a)**2),
    ("OBSCURANCE", lambda a: 4.0 / 3.0 * np.sqrt(a) - a**2 / 3.0),
])
def test_falloff_under_a_ceiling_matches_its_closed_form(falloff, expected):
    """Issue 18, item 5: each falloff against its closed form, not only their order."""
    caster = BVHCaster(*quads(CEILING))
    points, up = floor_points(np.linspace(-1, 1, 100))
    for max_distance in (1.25, 2.0, 4.0):
        params = AOParams(rays=256, max_distance=max_distance, falloff=falloff, adaptive=False)
        ao, _ = shade(points, up, up, np.arange(100), params, caster)
        assert abs(ao.mean() - expected(1.0 / max_distance)) < 0.01, (max_distance, ao.mean())


@pytest.mark.parametrize("bias", [15.0, 30.0, 60.0])
def test_horizon_bias_under_a_ceiling_matches_its_closed_form(bias):
    """A hit at elevation e occludes by min(e / bias, 1); under a ceiling reached by every ray (cosine
    rays: density sin 2e over e) the AO is 1/2 - sin(2 bias) / (4 bias)."""
    caster = BVHCaster(*quads(CEILING))
    points, up = floor_points(np.linspace(-1, 1, 100))
    params = AOParams(rays=256, max_distance=10 * BIG, horizon_bias=bias, adaptive=False)
    ao, _ = shade(points, up, up, np.arange(100), params, caster)
    beta = np.radians(bias)
    assert abs(ao.mean() - (0.5 - np.sin(2 * beta) / (4 * beta))) < 0.01, ao.mean()


def test_adaptive_sampling_changes_only_texels_that_stop_and_stays_within_the_noise():
    """Points that get every ray are bit-identical with and without adaptive sampling (same sequence);
    the ones that stop early differ by less than the noise of the full estimate."""
    caster = BVHCaster(*quads(FLOOR, WALL_X0))
    points, up = floor_points(np.linspace(0.02, 3.0, 300))
    full, full_rays = shade(points, up, up, np.arange(300), AOParams(rays=64, max_distance=1.0, adaptive=False),
                            caster)
    adaptive, adaptive_rays = shade(points, up, up, np.arange(300), AOParams(rays=64, max_distance=1.0), caster)
    assert adaptive_rays < 0.8 * full_rays                      # points beyond the wall's reach stop early
    changed = adaptive != full
    assert changed.sum() <= 300 - (adaptive_rays - 300 * 16) // 48
    assert np.abs(adaptive - full).max() <= 3.0 * 0.5 / np.sqrt(64), np.abs(adaptive - full).max()
