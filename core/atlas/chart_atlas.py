"""Charts to one packed atlas (thesis §7.6, with xatlas instead of its naive packer).

Every chart is its faces projected on the chart's axis plane (drop one
coordinate, :data:`..charts.clustering.BASES` keeps the image unmirrored), scaled by
one texel density for all charts.  :mod:`.packing` places the charts (xatlas
for the large ones, given their covers; shared shelf-packed boxes for the small
ones; one texel for those under a texel), never rotated, so side charts keep +Z
up; each chart's placement is an affine map from chart-plane coordinates to
texels, and every UV is computed from it in float64.  Texel coordinates: texel ``(x, y)`` covers
``[x, x+1] x [y, y+1]``, its centre is ``(x + 0.5, y + 0.5)``, row 0 is the
bottom row (Blender's image and UV convention); UV = texel / size.
"""

from dataclasses import dataclass, field

import numpy as np

from ..arrays.geometry2d import group_boxes
from ..charts.clustering import project_corners
from ..errors import SeamlessAOError
from ..mesh.extent import mesh_size
from .cover import chart_covers
from .packing import (MIN_PADDING, POINT_TEXELS, Packer, density_filling, effective_padding, largest_density,
                      xatlas_padding)


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


@dataclass
class Atlas:
    """Packed charts and the UVs of every triangle in every chart it belongs to.

    Attributes
    ----------
    width, height : int
        Image size in texels.
    density : float
        Texels per object unit, as packed (mean over charts).
    utilisation : float
        Fraction of the image covered by charts (as xatlas measures it).
    member_triangle : (m,) int64
        A *member* is one triangle in one chart: its triangle ...
    member_chart : (m,) int64
        ... and chart.
    member_uv : (m, 3, 2) float64
        Corners of the member in texel coordinates.
    membership : (t, 3) int64
        Member of each triangle on axis X, Y, Z (``-1``: not in a chart there).
    dominant_member : (t,) int64
        Member of each triangle on its face's dominant axis (never ``-1``).
    member_placed : (m,) bool
        False for members added for faces in no chart (zero area): they
        borrow a neighbour's chart and own no texels.
    charts : Charts
        The charts as packed.
    chart_texel : (c,) int64
        Flat texel index (``y * width + x``) of each chart stored as one
        texel (smaller than :data:`POINT_TEXELS` at this density; all its
        UVs are that texel's centre), ``-1`` for charts drawn in full.
    chart_texel_member : (c,) int64
        The member whose surface a one-texel chart's texel samples (its
        largest triangle), ``-1`` for the others.
    padding : int
        xatlas padding the charts were packed with (:func:`.packing.xatlas_padding`): the
        rasteriser fills this many rings around each chart.
    warnings : list of str
        Sentences for the user (tiny pieces that had to share texels).
    """

    width: int
    height: int
    density: float
    utilisation: float
    member_triangle: np.ndarray
    member_chart: np.ndarray
    member_uv: np.ndarray
    membership: np.ndarray
    dominant_member: np.ndarray
    member_placed: np.ndarray = None
    charts: object = field(default=None, repr=False)
    chart_texel: np.ndarray = None
    chart_texel_member: np.ndarray = None
    padding: int = 4
    warnings: list = field(default_factory=list)

    @property
    def size(self):
        return np.array([self.width, self.height], dtype=np.float64)

    def layer_uv(self):
        """(t, 3, 3, 2) float64: UV of each triangle corner in layers ``AO_X``, ``AO_Y``, ``AO_Z``
        (:meth:`axis_uv` of each axis, stacked)."""
        return np.stack([self.axis_uv(axis) for axis in range(3)], axis=1)

    def layer_member(self, axis, triangles=slice(None)):
        """(k,) int: the member each of ``triangles`` is read through in layer ``axis`` (its chart on that
        axis, else its dominant one)."""
        member = self.membership[triangles, axis]
        return np.where(member >= 0, member, self.dominant_member[triangles])

    def layer_drop(self, axis, triangles=slice(None)):
        """(k,) int8: the coordinate (0 x, 1 y, 2 z) that the chart each of ``triangles`` is read through in
        layer ``axis`` projects away: its UVs there are an affine function of the other two."""
        chart = self.member_chart[self.layer_member(axis, triangles)]
        return (self.charts.chart_axis[chart] // 2).astype(np.int8)

    def axis_uv(self, axis, triangles=slice(None)):
        """(k, 3, 2) float64: UV of each corner of ``triangles`` (a slice or (k,) int) in layer ``AO_X``,
        ``AO_Y`` or ``AO_Z`` (``axis`` 0, 1, 2), within half a texel of the image's border.

        A triangle with no chart on an axis repeats its dominant chart there
        (thesis §7.1.1), so all three lookups read the same surface.  One
        layer at a time: a bake writes the layers one by one, and the three
        together are 72 bytes per triangle (72 MB at a million triangles).
        """
        uv = self.member_uv[self.layer_member(axis, triangles)]
        # column by column: what ``uv /= size`` and ``np.clip`` compute, in a fifth of the time
        for column, size in enumerate((float(self.width), float(self.height))):
            values = uv[..., column]
            values /= size
            np.maximum(values, 0.5 / size, out=values)
            np.minimum(values, 1.0 - 0.5 / size, out=values)
        return uv


def chart_members(mesh, charts):
    """Every (triangle, chart) pair, degenerate triangles included.

    Returns
    -------
    member_triangle, member_chart : (m,) int64
    membership : (t, 3) int64
        Member index of each triangle per axis, ``-1`` where it has no chart.
    """
    per_axis = charts.chart_of_face[mesh.triangle_face]             # (t, 3)
    triangle, axis = np.nonzero(per_axis >= 0)
    membership = np.full(per_axis.shape, -1, dtype=np.int64)
    membership[triangle, axis] = np.arange(len(triangle))
    return triangle.astype(np.int64), per_axis[triangle, axis], membership


def _member_plane_area(mesh, charts, member_triangle, member_chart):
    """(m,) area of each member projected on its chart's plane: half the axis component of its cross product."""
    return 0.5 * np.abs(mesh.triangle_cross[member_triangle, charts.chart_axis[member_chart] // 2])


def expected_density(mesh, charts, image_size):
    """Texels per object unit at which the charts would fill about half an ``image_size`` image: the
    :func:`estimate_density` of their area, where the members longer than the image at that density count
    as :func:`long_chart_factors` will shrink them (a spike to a stray vertex counts for little)."""
    member_triangle, member_chart, _ = chart_members(mesh, charts)
    member_area = _member_plane_area(mesh, charts, member_triangle, member_chart)
    density = estimate_density(float(member_area.sum()), image_size)
    # a triangle's longest side (twice its area over its least height) is longer than any projection of it
    longest = 2.0 * mesh.triangle_area / np.maximum(mesh.corner_height.min(axis=1), 1e-300)
    if not longest.max(initial=0.0) * density > SHRUNK_CHART_SHARE * LONG_CHART_IMAGES * image_size:
        return density
    factor = long_chart_factors(longest[member_triangle], member_area, np.arange(len(member_area)),
                                LONG_CHART_IMAGES * image_size, image_size=image_size, utilisation=0.55,
                                stray=mesh.stray[member_triangle])
    return estimate_density(float((member_area * factor**2).sum()), image_size)


def estimate_density(area, image_size, utilisation=0.55):
    """Texels per object unit that would fill ``utilisation`` of a square image."""
    return float(np.sqrt(utilisation * image_size**2 / max(area, 1e-300)))


def pack_charts(mesh, topology, charts, padding=4, image_size=None, density=None, max_size=16384):
    """Pack all charts into one image; never fails for lack of room.

    Large charts go to xatlas as their coarse covers (:mod:`.cover`), a few
    triangles however many the chart has; small charts and charts under a
    texel (stored as one texel, every UV at its centre) are shelf-packed into
    shared boxes (:mod:`.packing` has the rules).  If even one texel per
    chart does not fit, neighbouring tiny charts share texels and
    :attr:`Atlas.warnings` says which image size would give each its own.
    The padding between large charts shrinks (down to
    :data:`.packing.MIN_PADDING`) where it would cost more than
    :data:`.packing.PADDING_OVERHEAD` of extra atlas area.

    Parameters
    ----------
    mesh : TriangleMesh
    topology : Topology
    charts : Charts
    padding : int
        Texels kept free between large charts (beyond the ring bilinear
        filtering reads, which is always kept), at most: it becomes xatlas'
        padding by :func:`.packing.xatlas_padding`.
    image_size : int, optional
        Square image size; the density is the largest that fits (within 3%),
        found by a search with a packing run as the test.
    density : float, optional
        Texels per object unit; the image is as large as needed (width and
        height rounded up to a multiple of 4).  Exactly one of ``image_size``
        and ``density`` must be given.
    max_size : int
        Refuse a ``density`` that needs a larger image.

    Returns
    -------
    Atlas
    """
    if (image_size is None) == (density is None):
        raise ValueError("give exactly one of image_size and density")
    member_triangle, member_chart, membership = chart_members(mesh, charts)
    local_uv = project_corners(mesh, member_triangle, charts.chart_axis[member_chart])
    live = ~mesh.degenerate[member_triangle]
    if not live.any():
        raise SeamlessAOError("The mesh has no face with area; there is nothing to pack")
    member_area = _member_plane_area(mesh, charts, member_triangle, member_chart)
    factor = _long_chart_scale(mesh, charts, local_uv, member_area, member_triangle, member_chart, live,
                               image_size, density)
    if (factor < 1.0).any():
        # a chart only moves and scales in its plane, so scaling its coordinates is all it takes
        local_uv *= factor[member_chart][:, None, None]
        member_area *= factor[member_chart] ** 2
    area = float(member_area[live].sum())
    expected = density if density is not None else estimate_density(area, image_size, 0.7)
    covers = chart_covers(local_uv[live], member_chart[live], charts.count, expected)
    if image_size is not None:
        # the density at which the charts' boxes with the least padding fill the image
        all_points = POINT_TEXELS / max(covers.extent.max(), 1e-300)
        expected = density_filling(covers.extent, MIN_PADDING, image_size**2, all_points,
                                   image_size / np.sqrt(max(area, 1e-300)))
    padding = effective_padding(covers.extent, expected, xatlas_padding(padding))
    packer = Packer(covers, _chart_centres(mesh, member_triangle, member_chart, charts.count), padding)
    placement = (largest_density(packer, int(image_size), area) if image_size is not None
                 else _place_at_density(packer, covers, area, density, padding, max_size))
    transforms = placement.transforms()                                    # (c, 2, 3)
    member_uv = _apply(transforms[member_chart], local_uv)
    placed = len(member_triangle)
    member_triangle, member_chart, member_uv, dominant_member = _members_with_orphans(
        mesh, topology, charts, membership, member_triangle, member_chart, member_uv, transforms, factor)
    point_member = _largest_member(mesh, member_triangle, member_chart, charts.count, placed,
                                   placement.point_texel >= 0)
    width, height = placement.width, placement.height                     # texels
    point_texels = len(np.unique(placement.point_texel[placement.point_texel >= 0]))
    drawn_area = float(member_area[live & (placement.point_texel[member_chart[:len(live)]] < 0)].sum())
    return Atlas(
        width=width, height=height, density=placement.density,
        utilisation=float(min(1.0, (drawn_area * placement.density**2 + point_texels) / (width * height))),
        member_triangle=member_triangle, member_chart=member_chart, member_uv=member_uv,
        membership=membership, dominant_member=dominant_member,
        member_placed=np.arange(len(member_triangle)) < placed,
        charts=charts, chart_texel=placement.point_texel, chart_texel_member=point_member,
        padding=padding, warnings=_long_chart_warning(factor) + placement.warnings())


def _members_with_orphans(mesh, topology, charts, membership, member_triangle, member_chart, member_uv, transforms,
                          factor):
    """The members with one more for each triangle of a face in no chart (zero area: a neighbour's chart,
    :func:`_adopt_orphans`), at the end; and ``dominant_member`` (t,): each triangle's member on its face's
    dominant axis (an orphan's own)."""
    orphan_triangle, orphan_chart = _adopt_orphans(mesh, topology, charts)
    if len(orphan_triangle):
        orphan_local = project_corners(mesh, orphan_triangle, charts.chart_axis[orphan_chart])
        orphan_local *= factor[orphan_chart][:, None, None]
        member_uv = np.concatenate([member_uv, _apply(transforms[orphan_chart], orphan_local)])
        member_triangle = np.concatenate([member_triangle, orphan_triangle])
        member_chart = np.concatenate([member_chart, orphan_chart])
    dominant_member = np.full(len(mesh.triangles), -1, dtype=np.int64)
    face_dominant = charts.dominant_axis[mesh.triangle_face]
    live_face = face_dominant >= 0
    dominant_member[live_face] = membership[live_face, face_dominant[live_face] // 2]
    dominant_member[orphan_triangle] = len(member_triangle) - len(orphan_triangle) + np.arange(len(orphan_triangle))
    return member_triangle, member_chart, member_uv, dominant_member


def _long_chart_scale(mesh, charts, local_uv, member_area, member_triangle, member_chart, live, image_size, density):
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


def _place_at_density(packer, covers, area, density, padding, max_size):
    """The placement at a given texel ``density``, or a :class:`SeamlessAOError` where it needs an image over
    ``max_size`` (asked before xatlas runs: it has no memory limit of its own) or cannot be laid out."""
    needed = max(np.sqrt(area) * density, float(covers.extent.max()) * density + 2 * padding)
    if needed > max_size:
        raise SeamlessAOError(
            "A texel density of {:g} needs an image of about {:.0f} texels or more across, larger than {}; "
            "lower the density".format(density, needed, max_size))
    placement = packer.place(density, 0, share=1)
    if placement is None:                       # xatlas reshaped a chart: no layout at this density
        raise SeamlessAOError(
            "Could not lay out the charts at a texel density of {:g}; choose Image Size instead".format(density))
    if max(placement.width, placement.height) > max_size:
        raise SeamlessAOError("A texel density of {:g} needs a {}x{} image, larger than {}; lower the density".format(
            density, placement.width, placement.height, max_size))
    return placement


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


def _long_chart_warning(factor):
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


def _chart_centres(mesh, member_triangle, member_chart, chart_count):
    """(c, 3) mean of the triangle centres of each chart (object units)."""
    first, second, third = (mesh.positions[mesh.triangles[member_triangle, k]] for k in range(3))
    centre = (first + second + third) / 3.0
    count = np.maximum(np.bincount(member_chart, minlength=chart_count), 1)
    return np.stack([np.bincount(member_chart, centre[:, k], chart_count) for k in range(3)], axis=1) / count[:, None]


def _largest_member(mesh, member_triangle, member_chart, chart_count, placed_count, wanted):
    """(c,) the largest live member of each ``wanted`` chart ((c,) bool; -1 for the others and for charts with
    none): only their members are sorted."""
    members = np.flatnonzero(wanted[member_chart[:placed_count]])
    area = np.where(mesh.degenerate[member_triangle[members]], -1.0, mesh.triangle_area[member_triangle[members]])
    order = np.lexsort((-area, member_chart[members]))
    chart_sorted = member_chart[members][order]
    first = np.ones(len(order), dtype=bool)
    first[1:] = chart_sorted[1:] != chart_sorted[:-1]
    first &= area[order] >= 0.0                  # a chart whose largest member is degenerate has none live
    best = np.full(chart_count, -1, dtype=np.int64)
    best[chart_sorted[first]] = members[order[first]]
    return best


def _apply(transform, points):
    """Affine ``transform`` (m, 2, 3) applied to ``points`` (m, k, 2)."""
    u, v = points[..., 0], points[..., 1]
    t = transform[:, None]                                                  # (m, 1, 2, 3)
    return np.stack([t[..., 0, 0] * u + t[..., 0, 1] * v + t[..., 0, 2],
                     t[..., 1, 0] * u + t[..., 1, 1] * v + t[..., 1, 2]], axis=-1)


def _adopt_orphans(mesh, topology, charts):
    """A chart for every triangle of a face in no chart: a charted neighbour's dominant chart.

    Returns ``(triangles, charts)`` as (k,) int64 arrays; a face with no
    charted neighbour takes chart 0 (it is too small to show anything).
    """
    dead_face = (charts.chart_of_face < 0).all(axis=1)
    if not dead_face.any():
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    dominant_chart = charts.dominant_chart()
    adopted = np.zeros(mesh.face_count, dtype=np.int64)
    edges = topology.face_edges
    for a, b in ((0, 1), (1, 0)):
        link = dead_face[edges[:, a]] & ~dead_face[edges[:, b]]
        # later edges overwrite earlier ones: the largest live neighbour wins, deterministically
        adopted[edges[link, a]] = dominant_chart[edges[link, b]]
    triangles = np.flatnonzero(dead_face[mesh.triangle_face])
    return triangles, adopted[mesh.triangle_face[triangles]]
