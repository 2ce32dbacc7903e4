"""A stand-in for the Blender side's Cycles caster in tests on arrays: a BVH caster that also shades whole
texels (core/rays/job.py hands it every ray after the pilot)."""

import numpy as np

from seamless_ao.core.rays.ray_setup import BVHCaster


class WholeTexelCaster(BVHCaster):
    """A BVH caster that also shades whole texels (as the Blender side's Cycles caster does): every texel
    it is asked for is open by ``open_fraction``; it records each call's texel count and samples, and how
    many calls came before it was told casting was done (after which it refuses to cast)."""

    bakes_whole_texels = True

    def __init__(self, positions, triangles, sealed=None, open_fraction=0.25):
        super().__init__(positions, triangles, sealed)
        self.open_fraction = open_fraction
        self.rays_cast = 0
        self.calls = []
        self.done_after = None

    def cast(self, origins, directions, max_distance):
        assert self.done_after is None, "a ray cast after casting_done"
        self.rays_cast += len(origins)
        return super().cast(origins, directions, max_distance)

    def casting_done(self):
        assert self.done_after is None, "casting_done twice"
        self.done_after = len(self.calls)

    def ambient_occlusion(self, points, normals, geometric, samples, params):
        self.calls.append((len(points), samples))
        return np.full(len(points), self.open_fraction)
