"""How much memory a bake will need, estimated before it starts (the memory budget setting)."""

from .errors import SeamlessAOError
from .rays.cycles_rules import CYCLES_BYTES_PER_TRIANGLE, CYCLES_FIXED_BYTES

#: Charts overlap: the three projections together cover about this much more than the surface.
CHART_OVERLAP = 1.5
#: Fraction of the image the packed charts cover, and of that the texels that land on the mesh.
ATLAS_USE = 0.5
TEXEL_FRACTION = 0.8


#: Bytes per triangle, per texel, per image pixel, and a fixed part (ray batches): a least-squares fit
#: (of the relative error) to the peaks ``tests/bench/bench_memory.py`` measures on its eight bakes.
PER_TRIANGLE = 1600
PER_TEXEL = 92
PER_PIXEL = 24
FIXED = 56 * 2**20


def estimated_bytes(triangles, texels, pixels, cycles=False):
    """Peak memory a bake adds, in bytes: per-triangle arrays (mesh, charts, atlas, caster), per-texel
    arrays (points, normals, sums, denoiser), dense image-sized maps, and ray batches; with ``cycles`` (the
    Cycles caster casts the bulk) Cycles' own scene and its copy of the triangles too."""
    ours = FIXED + PER_TRIANGLE * triangles + PER_TEXEL * texels + PER_PIXEL * pixels
    return int(ours + (CYCLES_FIXED_BYTES + CYCLES_BYTES_PER_TRIANGLE * triangles if cycles else 0))


def planned_size(settings, surface_area):
    """(image pixels, texels) a bake is expected to need before its atlas exists.

    ``surface_area`` is the meshes' total area in scene units²; with Texel
    Density the image grows with it.
    """
    if settings.size_mode == "IMAGE_SIZE":
        pixels = settings.image_size**2
    else:
        pixels = surface_area * CHART_OVERLAP * settings.texel_density**2 / ATLAS_USE
    return pixels, pixels * TEXEL_FRACTION


def check_budget(settings, triangles, pixels, texels):
    """Raise :class:`SeamlessAOError` if the estimate exceeds ``settings.memory_budget_mb`` (Cycles' part counted
    where the settings take the Cycles caster)."""
    needed = estimated_bytes(triangles, texels, pixels, settings.caster_name() == "CYCLES") / 2**20
    if needed > settings.memory_budget_mb:
        raise SeamlessAOError(
            "This bake would need about {:,.0f} MB, more than the memory budget of {:,} MB; lower the image "
            "size or texel density, or raise the budget".format(needed, settings.memory_budget_mb))
