"""Charts too long for the image: a stray spike, one long face, debris far off.  Each is packed at a lower
density of its own (:func:`long_chart_factors`), so one face cannot set the density of the whole image."""

import numpy as np

from ..arrays.geometry2d import group_boxes
from ..mesh.extent import mesh_size


#: A chart longer than this many image widths at the density that would fill the image
#: (:func:`estimate_density`) is packed at a lower density of its own: one stray face must not
#: take the texels of the whole mesh (:func:`long_chart_factors`).
LONG_CHART_IMAGES = 1.0
#: Such a chart is packed this share of that long (a spike's texels show next to nothing).
SHRUNK_CHART_SHARE = 0.25
#: With a texel density given, a chart longer than this many texels is packed at a lower density of its own,
LONG_CHART_TEXELS = 4096
#: ... if such charts hold at most this share of the triangles (a few stray faces, not the mesh itself).
FEW_LONG_MEMBERS = 0.01


def estimate_density(area, image_size, utilisation=0.55):
    """Texels per object unit that would fill ``utilisation`` of a square image."""
    return float(np.sqrt(utilisation * image_size**2 / max(area, 1e-300)))


def long_chart_scale(mesh, charts, local_uv, member_area, member_triangle, member_chart, live, image_size, density):
    """(c,) float: each chart's own scale, 1 but for the long charts :func:`long_chart_factors` shrinks."""
    factor = np.ones(charts.count)
    if not _may_be_long(mesh, float(member_area[live].sum()), image_size, density):
        return factor
    # chart boxes from the members (covers at the common density first would band a spike's chart 10^9 times)
    low, high = group_boxes(local_uv[live], member_chart[live], charts.count)
    longest = np.where(np.isfinite(low[:, 0]), (high - low).max(axis=1), 0.0)
    stray = np.zeros(charts.count, dtype=bool)
    stray[member_chart[mesh.stray[member_triangle]]] = True
    if image_size is not None:
        return long_chart_factors(longest, member_area[live], member_chart[live], LONG_CHART_IMAGES * image_size,
                                  image_size=image_size, stray=stray)
    factor = long_chart_factors(longest, member_area[live], member_chart[live], LONG_CHART_TEXELS,
                                density=density, stray=stray)
    if (factor[member_chart[live]] < 1.0).mean() > FEW_LONG_MEMBERS:
        factor[:] = 1.0             # the mesh itself is that large at this density: refused below
    return factor


def long_chart_factors(longest, member_area, member_chart, limit, image_size=None, density=None, utilisation=0.7,
                       stray=None):
    """(c,) float64 in (0, 1]: the share of the common texel density each chart is packed at.

    A chart longer than ``limit`` texels at the density the layout expects
    (``density``, or :func:`estimate_density` of the charts' area in an
    ``image_size`` image) gets :data:`SHRUNK_CHART_SHARE` of ``limit``
    texels along its longer side (before the density search scales all
    charts alike), and so does a ``stray`` chart longer than that (one
    holding triangles the mesh's size leaves out, :attr:`..mesh.triangle_mesh.TriangleMesh.stray`:
    a sheet of spikes to far outliers is more surface than the rest); the
    others keep the common density (1).  Long charts are cut into pieces
    before (:func:`..charts.clustering.cut_long_charts`), but not their faces: a
    spike to a stray vertex, or one long quad, is one face however long.
    Without this, the density search would shrink every chart until that
    one fits.  With ``image_size``, the expected density is that of the
    area once the long charts are shrunk.

    Parameters
    ----------
    longest : (c,) float64, object units: each chart's longer side in its plane
    member_area : (m,) float64, object units squared; member_chart : (m,) int
    limit : float, texels
    utilisation : float, of the image, for :func:`estimate_density`
    stray : (c,) bool, optional
    """
    target = SHRUNK_CHART_SHARE * limit
    trigger = np.full(len(longest), float(limit)) if stray is None else np.where(stray, target, float(limit))
    longest = np.maximum(longest, 1e-300)
    if density is not None:
        return np.where(longest * density > trigger, target / (longest * density), 1.0)
    # Shrunk to ``target`` texels long, a chart takes area * (target / longest)^2 texels whatever the density,
    # so the density that fills the image with the rest follows from the set of shrunk charts directly.
    area = np.bincount(member_chart, member_area, len(longest))
    room = utilisation * float(image_size) ** 2
    shrunk = np.zeros(len(longest), dtype=bool)
    for _ in range(16):
        rest = float(area[~shrunk].sum())
        held = float((area[shrunk] * (target / longest[shrunk]) ** 2).sum())
        if rest > 0.0 and room > held:
            expected = np.sqrt((room - held) / rest)
        else:                         # the long charts alone would fill the image: as if none were shrunk
            expected = estimate_density(float(area.sum()), image_size, utilisation)
        now = longest * expected > trigger
        if np.array_equal(now, shrunk):
            break
        shrunk = now
    factor = np.where(shrunk, target / (longest * expected), 1.0)
    return factor


def _may_be_long(mesh, area, image_size, density):
    """Whether :func:`long_chart_factors` may shrink a chart: never when the whole mesh's box, at the density
    it starts from, is within the length it shrinks charts from (a quarter of that with debris): no chart is
    longer than the box's diagonal, and the density only grows once a chart is shrunk."""
    reach = mesh_size(mesh.positions)
    shortest = SHRUNK_CHART_SHARE if mesh.stray.any() else 1.0
    if density is not None:
        return reach * density > shortest * LONG_CHART_TEXELS
    return reach * estimate_density(area, image_size, 0.7) > shortest * LONG_CHART_IMAGES * image_size


def long_chart_warning(factor):
    """Sentences for the bake report about charts :func:`long_chart_factors` shrank."""
    shrunk = factor < 1.0
    if not shrunk.any():
        return []
    return ["{:,} chart{} too long for the image or far out of the rest of the mesh (a spike to a stray vertex, "
            "debris far off): packed with {} times fewer texels per unit than the rest".format(
                int(shrunk.sum()), "s were" if shrunk.sum() > 1 else " was", _times(1.0 / float(factor.min())))]


def _times(ratio):
    """``ratio`` >= 1 for a sentence: "up to 1.4", "up to 206", "over a million"."""
    if ratio >= 1e6:
        return "over a million"
    return "up to {:,.1f}".format(ratio) if ratio < 10 else "up to {:,.0f}".format(ratio)
