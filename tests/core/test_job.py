"""The ray schedule of a bake (core/rays/job.py): pilot and remaining rays, and weighted rays per texel."""

import numpy as np
import pytest

import meshes
from whole_texel_caster import WholeTexelCaster
from seamless_ao.core.image.shown import blend_weights
from seamless_ao.core.rays import job as job_module
from seamless_ao.core.rays.job import MIN_SHARED_RAYS, AOJob
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.layout import build_layout
from seamless_ao.core.atlas.raster import texel_geometry
from seamless_ao.core.rays.ray_setup import BVHCaster, ray_part
from seamless_ao.core.rays.cycles_rules import BULK_PILOT_RAYS
from seamless_ao.core.settings import BakeSettings
from seamless_ao.core.rays.targets import MAX_RAY_HALVINGS, RING_RAY_HALVINGS, TexelTargets, ray_shares


@pytest.fixture(scope="module")
def torus_layout():
    mesh = TriangleMesh.from_triangles(*meshes.torus(rings=32, segments=16), smooth=True)
    return build_layout(mesh, image_size=64)


def run(layout, rays, weighted, adaptive=False):
    """The bake's own schedule of rays for the layout's texels (the ray setup as core/pipeline.py makes it),
    the torus lying on a ground plane, so its lower half is well occluded."""
    settings = BakeSettings(quality="CUSTOM", rays=rays, adaptive=adaptive, auto_distance=False, max_distance=3.0,
                            use_ground_plane=True)
    part = ray_part(layout.mesh, np.eye(4), settings, BVHCaster)
    job = AOJob(TexelTargets(layout), [part], weighted=weighted)
    while not job.finished:
        job.step()
    return job


def test_weighted_rays_never_fall_below_what_a_texels_own_blend_weight_asks(torus_layout):
    layout = torus_layout
    job = run(layout, 32, weighted=True)
    halvings = ray_shares(layout, job.computed)
    computed = np.flatnonzero(job.computed)
    _, normals, _ = texel_geometry(layout.texels, layout.atlas, layout.mesh, computed)
    axis = layout.charts.chart_axis[layout.atlas.member_chart[layout.texels.member[computed]]] // 2
    own_weight = blend_weights(normals)[np.arange(len(computed)), axis]
    # halved h times only where the texel is shown with weight at most 2^-h
    assert (own_weight <= 2.0 ** -halvings[computed] + 1e-9).all()
    assert set(np.unique(halvings[computed])) >= {0, 1}                 # a torus has both kinds
    assert halvings.max() <= MAX_RAY_HALVINGS
    # a padding ring's share is halved once more, never beyond MAX_RAY_HALVINGS in all
    halvings = np.minimum(halvings + (layout.texels.ring > 0) * RING_RAY_HALVINGS, MAX_RAY_HALVINGS)
    expected = np.maximum(MIN_SHARED_RAYS, 32 >> halvings[computed])
    assert np.array_equal(job.ray_count[computed], np.where(halvings[computed] == 0, 32, expected))
    assert job.rays_cast == job.ray_count[computed].sum() < 32 * len(computed)


def test_weighted_rays_keep_full_texels_bit_identical_and_the_rest_within_their_noise(torus_layout):
    layout = torus_layout
    plain = run(layout, 32, weighted=False)
    weighted = run(layout, 32, weighted=True)
    full = weighted.computed & (weighted.ray_count == 32)
    assert np.array_equal(weighted.ao[full], plain.ao[full])           # same rays, same sums
    cut = weighted.computed & (weighted.ray_count < 32)
    difference = weighted.ao[cut] - plain.ao[cut]
    # per ray count: the RMS difference is within the binomial noise of that many rays (the weighted rays are a
    # stratified prefix of the plain ones, so it is well inside)
    for count in np.unique(weighted.ray_count[cut]):
        mine = weighted.ray_count[cut] == count
        ao = plain.ao[cut][mine]
        assert np.sqrt(np.mean(difference[mine] ** 2)) <= np.sqrt(np.mean(ao * (1.0 - ao)) / count), count
    # unbiased: the mean difference is within the noise of the mean (binomial variance of each estimate)
    ao = plain.ao[cut]
    variance = ao * (1.0 - ao) * (1.0 / weighted.ray_count[cut] + 1.0 / 32)
    assert (1.0 - ao).mean() > 0.05                                    # occluded enough to show a bias
    assert abs(difference.mean()) <= 4.0 * np.sqrt(variance.sum()) / cut.sum() + 1e-3


@pytest.mark.parametrize("rays", [32, 4])
def test_a_padding_ring_gets_half_the_rays_and_what_a_point_reads_gets_all(torus_layout, rays):
    """Covered and near texels (what bilinear filtering reads at the chart's points) get every ray; the
    first padding ring, which only the denoiser and mip-maps read, half of them (never below
    MIN_SHARED_RAYS); farther rings none."""
    layout = torus_layout
    job = run(layout, rays, weighted=False)
    ring = layout.texels.ring
    assert (ring == 1).any() and (ring > 1).any()                        # the torus has both kinds of ring
    assert np.array_equal(job.computed, ring <= 1)
    assert (job.ray_count[ring == 0] == rays).all()
    assert (job.ray_count[ring == 1] == max(MIN_SHARED_RAYS, rays >> RING_RAY_HALVINGS)).all()
    assert (job.ray_count[ring > 1] == 0).all()
    assert job.rays_cast == job.ray_count.sum()


def test_adaptive_stop_with_weighted_rays_scales_each_texel_to_its_own_count(torus_layout):
    """A texel that stops after its pilot rays all agreed counts them as all of its own rays: its AO is exactly
    0 (all blocked) or 1 (all open), whatever its class's ray count (scaled by the pilot count, or by another
    class's count, a blocked texel would show 1 - pilot / count)."""
    job = run(torus_layout, 64, weighted=True, adaptive=True)
    values = job.ao[job.computed]
    assert np.isfinite(values).all() and values.min() >= 0.0 and values.max() <= 1.0
    stopped = job.computed & (job.cast_count < job.ray_count)
    assert len(np.unique(job.ray_count[stopped])) >= 2                   # stops in more than one class
    assert set(np.unique(job.ao[stopped])) == {0.0, 1.0}                 # both kinds of stop
    assert np.array_equal(job.sums[stopped], np.where(job.ao[stopped] == 0.0, job.ray_count[stopped], 0.0))
    assert job.rays_cast == job.cast_count.sum() < job.ray_count[job.computed].sum()


@pytest.mark.parametrize("kept", [True, False])
def test_texel_targets_give_every_selection_the_geometry_of_its_own_texels(torus_layout, kept, monkeypatch):
    # Kept or computed per call (over GEOMETRY_CACHE_TEXELS), a selection reads its own texels' points and
    # normals, in its own order, bit for bit as texel_geometry computes them.
    import seamless_ao.core.rays.targets as targets_module
    monkeypatch.setattr(targets_module, "GEOMETRY_CACHE_TEXELS", 1 << 30 if kept else 0)
    targets = TexelTargets(torus_layout)
    layout = torus_layout
    computed = np.flatnonzero(targets.computed)
    rng = np.random.default_rng(5)
    for selection in (computed[::-1], rng.choice(computed, 300, replace=False), computed[:1]):
        expected = texel_geometry(layout.texels, layout.atlas, layout.mesh, selection)
        for got, want in zip(targets.geometry(selection), expected):
            assert got.shape == want.shape and np.array_equal(got, want)
    assert (targets._geometry is not None) == kept


@pytest.mark.parametrize("adaptive", [False, True])
def test_a_caster_that_shades_whole_texels_gets_every_ray_after_the_pilot(torus_layout, adaptive, monkeypatch):
    """The pilot rays (BULK_PILOT_RAYS, with or without the adaptive stop, which does not apply) are cast
    ray by ray; the other rays of every texel go to ``ambient_occlusion`` and count with their number."""
    monkeypatch.setattr(job_module, "BULK_LEAST_RAYS", 1)           # the torus is small: hand it over anyway
    layout = torus_layout
    settings = BakeSettings(quality="CUSTOM", rays=64, adaptive=adaptive, auto_distance=False, max_distance=3.0)
    part = ray_part(layout.mesh, np.eye(4), settings,
                    lambda positions, triangles, sealed: WholeTexelCaster(positions, triangles, sealed))
    caster = part.caster
    job = AOJob(TexelTargets(layout), [part])
    while not job.finished:
        job.step()
    computed = job.computed
    pilot = BULK_PILOT_RAYS
    count = job.ray_count[computed]                          # 64, and half of it in the padding ring
    assert set(np.unique(count)) == {64, 64 >> RING_RAY_HALVINGS}
    assert caster.calls and {samples for _, samples in caster.calls} == set(np.unique(count) - pilot)
    assert sum(texels for texels, _ in caster.calls) == computed.sum() and not job.settled.any()
    assert caster.rays_cast == pilot * computed.sum()       # the pilot only: a lone torus buries nothing
    assert job.rays_cast == count.sum()
    # each texel: its pilot rays' occlusion plus 3/4 of the others
    ray_sums = job.sums[computed]
    assert np.isfinite(job.ao).all() and (job.ao >= 0).all() and (job.ao <= 1).all()
    assert (ray_sums >= 0.75 * (count - pilot) - 1e-9).all() and (ray_sums <= pilot + 0.75 * (count - pilot) + 1e-9).all()
    assert (ray_sums > 0.75 * (count - pilot) + 0.5).any()   # some pilot rays meet the torus' own ring
    assert np.allclose(job.ao[computed], 1.0 - ray_sums / count)


def test_a_small_part_keeps_its_rays_with_the_node_and_a_large_one_hands_them_over(monkeypatch):
    """Two meshes baked together, each with its own whole-texel caster: the part with fewer than
    BULK_LEAST_RAYS rays after the pilot is cast as by a caster that shades no whole texels (its own pilot,
    the adaptive stop, ray by ray; no ``ambient_occlusion`` call, each has a fixed cost): the same sums
    as a plain BVH bake of it; the other hands all its rays after BULK_PILOT_RAYS over."""
    large = TriangleMesh.from_triangles(*meshes.torus(rings=32, segments=16), smooth=True)
    small = TriangleMesh.from_triangles(*meshes.box(size=(0.3, 0.3, 0.3), center=(3.0, 0.0, 0.0)))
    layout = build_layout([large, small], image_size=96)
    targets = TexelTargets(layout)
    rays = 64
    left = rays - BULK_PILOT_RAYS
    computed = np.flatnonzero(targets.computed)
    part_of = targets.part_of(computed)
    texels_of = np.bincount(part_of, minlength=2)
    assert texels_of[0] > 4 * texels_of[1] > 0
    monkeypatch.setattr(job_module, "BULK_LEAST_RAYS", int(texels_of[0] + texels_of[1]) * left // 2)
    settings = BakeSettings(quality="CUSTOM", rays=rays, adaptive=True, auto_distance=False, max_distance=3.0)

    def bake(make_caster):
        parts = [ray_part(mesh, np.eye(4), settings, make_caster) for mesh in (large, small)]
        job = AOJob(targets, parts)
        while not job.finished:
            job.step()
        return job, [part.caster for part in parts]

    job, (big, little) = bake(lambda positions, triangles, sealed: WholeTexelCaster(positions, triangles, sealed))
    plain, _ = bake(BVHCaster)
    assert sum(count for count, _ in big.calls) == texels_of[0] and big.rays_cast == BULK_PILOT_RAYS * texels_of[0]
    assert not job.settled[computed[part_of == 0]].any()
    assert not little.calls
    # the small part casts ray by ray to the end (its buried texels follow all its rays): nobody is done
    assert big.done_after is None and little.done_after is None
    in_little = computed[part_of == 1]
    assert job.settled[in_little].any()                       # the adaptive stop, as without Cycles
    assert np.array_equal(job.sums[in_little], plain.sums[in_little])
    assert np.array_equal(job.ao[in_little], plain.ao[in_little])
    assert np.isfinite(job.ao).all()


def test_a_whole_texel_caster_shades_the_creases_too(monkeypatch):
    """A box pushed into another (texels of each inside the other are buried): the rim of each buried
    region is shaded at its crease points by ``ambient_occlusion`` (all rays, given points) when the part's
    other rays go there too.  The fake caster says 0.3 open everywhere, so a crease texel's AO is exactly
    0.3, which no texel with pilot rays of its own can show (1 - (p + 0.7 x 60) / 64 for p of 4)."""
    monkeypatch.setattr(job_module, "BULK_LEAST_RAYS", 1)
    positions, triangles, _ = meshes.pierced_box()
    mesh = TriangleMesh.from_triangles(positions, triangles)
    layout = build_layout(mesh, image_size=128)
    settings = BakeSettings(quality="CUSTOM", rays=64, auto_distance=False, max_distance=3.0)
    part = ray_part(layout.mesh, np.eye(4), settings,
                    lambda positions, triangles, sealed: WholeTexelCaster(positions, triangles, sealed, 0.3))
    job = AOJob(TexelTargets(layout), [part])
    while not job.finished:
        job.step()
    crease_calls = [count for count, samples in part.caster.calls if samples == 64]
    assert crease_calls and sum(crease_calls) > 10
    creased = np.isclose(job.ao, 0.3, atol=1e-6) & job.computed
    assert creased.sum() == sum(crease_calls)
    assert not job.buried[creased].any() and np.isfinite(job.ao).all()
    # The creases are found right after the pilot: the caster is told no ray comes after them before its
    # first bake (its cast refuses any later ray).  Their rim texels stay in the bulk's batches (every
    # texel's Cycles pixel as when the creases came last), and only their crease counts: 0.3 exactly.
    assert part.caster.done_after == 0
    assert sum(count for count, _ in part.caster.calls) == job.computed.sum() + creased.sum()
