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

from ..arrays.blocks import row_blocks
from ..arrays.graph import index_type
from ..arrays.reduce import row_all
from ..charts.clustering import project_corners
from ..errors import SeamlessAOError
from .cover import chart_covers
from .long_charts import (LONG_CHART_IMAGES, SHRUNK_CHART_SHARE, estimate_density, long_chart_factors, long_chart_scale,
                          long_chart_warning)
from .packing import (MIN_PADDING, POINT_TEXELS, Packer, density_filling, effective_padding, largest_density,
                      xatlas_padding)


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
    membership : (t, 3) int32 (int64 past 2**31 members)
        Member of each triangle on axis X, Y, Z (``-1``: not in a chart there).
    dominant_member : (t,) int32 (int64 past 2**31 members)
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

    def axis_uv(self, axis, triangles=slice(None), dtype=np.float64):
        """(k, 3, 2) UV of each corner of ``triangles`` (a slice or (k,) int) in layer ``AO_X``, ``AO_Y`` or
        ``AO_Z`` (``axis`` 0, 1, 2), within half a texel of the image's border: worked out in float64, returned
        as ``dtype`` (float32: what a UV map holds, rounded once, half the bytes).

        A triangle with no chart on an axis repeats its dominant chart there
        (thesis §7.1.1), so all three lookups read the same surface.  One
        layer at a time, a block of rows at a time (:func:`..arrays.blocks.row_blocks`): a bake writes the
        layers one by one, and the three together are 72 bytes per triangle in float64 (72 MB at a million).
        """
        member = self.layer_member(axis, triangles)
        uv = np.empty((len(member), 3, 2), dtype=dtype)
        sizes = (float(self.width), float(self.height))
        for rows in row_blocks(len(member)):
            block = self.member_uv[member[rows]]
            # what ``block /= size`` and ``np.clip`` compute, in a fifth of the time: over the whole block at
            # once where u and v share a size (a square image), else column by column
            for column, size in ([(Ellipsis, sizes[0])] if sizes[0] == sizes[1] else
                                 [((Ellipsis, 0), sizes[0]), ((Ellipsis, 1), sizes[1])]):
                values = block[column]
                values /= size
                np.maximum(values, 0.5 / size, out=values)
                np.minimum(values, 1.0 - 0.5 / size, out=values)
            uv[rows] = block
        return uv


def chart_members(mesh, charts):
    """Every (triangle, chart) pair, degenerate triangles included.

    Returns
    -------
    member_triangle, member_chart : (m,) int64
    membership : (t, 3) int32 (int64 past 2**31 members)
        Member index of each triangle per axis, ``-1`` where it has no chart.
    """
    per_axis = charts.chart_of_face[mesh.triangle_face]             # (t, 3)
    triangle, axis = np.nonzero(per_axis >= 0)
    membership = np.full(per_axis.shape, -1, dtype=index_type(len(triangle) + len(mesh.triangles)))
    membership[triangle, axis] = np.arange(len(triangle))
    return triangle.astype(np.int64), per_axis[triangle, axis], membership


def _member_plane_area(mesh, charts, member_triangle, member_chart):
    """(m,) area of each member projected on its chart's plane: half the axis component of its cross product."""
    return 0.5 * np.abs(mesh.triangle_cross[member_triangle, charts.chart_axis[member_chart] // 2])


def expected_density(mesh, charts, image_size):
    """Texels per object unit at which the charts would fill about half an ``image_size`` image: the
    :func:`estimate_density` of their area, where the members longer than the image at that density count
    as :func:`.long_charts.long_chart_factors` will shrink them (a spike to a stray vertex counts for little)."""
    member_triangle, member_chart, _ = chart_members(mesh, charts)
    member_area = _member_plane_area(mesh, charts, member_triangle, member_chart)
    density = estimate_density(float(member_area.sum()), image_size)
    # a triangle's longest side is longer than any projection of it
    longest = mesh.longest_side
    if not longest.max(initial=0.0) * density > SHRUNK_CHART_SHARE * LONG_CHART_IMAGES * image_size:
        return density
    factor = long_chart_factors(longest[member_triangle], member_area, np.arange(len(member_area)),
                                LONG_CHART_IMAGES * image_size, image_size=image_size, utilisation=0.55,
                                stray=mesh.stray[member_triangle])
    return estimate_density(float((member_area * factor**2).sum()), image_size)


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
    factor = long_chart_scale(mesh, charts, local_uv, member_area, member_triangle, member_chart, live,
                               image_size, density)
    if (factor < 1.0).any():
        # a chart only moves and scales in its plane, so scaling its coordinates is all it takes
        local_uv *= factor[member_chart][:, None, None]
        member_area *= factor[member_chart] ** 2
    area = float(member_area[live].sum())
    expected = density if density is not None else estimate_density(area, image_size, 0.7)
    every = bool(live.all())                  # then no copy of every member's corners (48 MB a million)
    covers = chart_covers(local_uv if every else local_uv[live], member_chart if every else member_chart[live],
                          charts.count, expected)
    if image_size is not None:
        # the density at which the charts' boxes with the least padding fill the image
        all_points = POINT_TEXELS / max(covers.extent.max(), 1e-300)
        expected = density_filling(covers.extent, MIN_PADDING, image_size**2, all_points,
                                   image_size / np.sqrt(max(area, 1e-300)))
    padding = effective_padding(covers.extent, expected, xatlas_padding(padding))
    packer = Packer(covers, _chart_centres(mesh, member_triangle, member_chart, charts.count), padding)
    placement = (largest_density(packer, int(image_size), area) if image_size is not None
                 else _place_at_density(packer, covers, area, density, padding, max_size))
    maps = placement.maps()
    member_uv = _apply(maps, member_chart, local_uv)
    del local_uv
    placed = len(member_triangle)
    member_triangle, member_chart, member_uv, dominant_member = _members_with_orphans(
        mesh, topology, charts, membership, member_triangle, member_chart, member_uv, maps, factor)
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
        padding=padding, warnings=long_chart_warning(factor) + placement.warnings())


def _members_with_orphans(mesh, topology, charts, membership, member_triangle, member_chart, member_uv, maps,
                          factor):
    """The members with one more for each triangle of a face in no chart (zero area: a neighbour's chart,
    :func:`_adopt_orphans`), at the end; and ``dominant_member`` (t,): each triangle's member on its face's
    dominant axis (an orphan's own)."""
    orphan_triangle, orphan_chart = _adopt_orphans(mesh, topology, charts)
    if len(orphan_triangle):
        orphan_local = project_corners(mesh, orphan_triangle, charts.chart_axis[orphan_chart])
        orphan_local *= factor[orphan_chart][:, None, None]
        member_uv = np.concatenate([member_uv, _apply(maps, orphan_chart, orphan_local)])
        member_triangle = np.concatenate([member_triangle, orphan_triangle])
        member_chart = np.concatenate([member_chart, orphan_chart])
    dominant_member = np.full(len(mesh.triangles), -1, dtype=membership.dtype)
    face_dominant = charts.dominant_axis[mesh.triangle_face]
    live_face = face_dominant >= 0
    dominant_member[live_face] = membership[live_face, face_dominant[live_face] // 2]
    dominant_member[orphan_triangle] = len(member_triangle) - len(orphan_triangle) + np.arange(len(orphan_triangle))
    return member_triangle, member_chart, member_uv, dominant_member


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


def _chart_centres(mesh, member_triangle, member_chart, chart_count):
    """(c, 3) mean of the triangle centres of each chart (object units): one coordinate at a time, each
    triangle's centre once however many charts it is in."""
    count = np.maximum(np.bincount(member_chart, minlength=chart_count), 1)
    centres = np.empty((chart_count, 3))
    first, second, third = mesh.triangles.T
    for k in range(3):
        column = np.ascontiguousarray(mesh.positions[:, k])
        centre = column[first] + column[second]
        centre += column[third]
        centre /= 3.0
        centres[:, k] = np.bincount(member_chart, centre[member_triangle], chart_count) / count
    return centres


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


def _apply(maps, chart, points):
    """``points`` (m, k, 2), each moved by the map ``(scale (c,), shift (c, 2))`` of its ``chart`` (m,) int
    (:meth:`.packing.Placement.maps`: ``scale * u + shift``), in place; returns ``points``.  A block of members
    at a time (:func:`..arrays.blocks.row_blocks`): the gathered scales and shifts stay small; the shift a
    coordinate at a time (added over a trailing axis of two, numpy goes two items at a time)."""
    scale, shift = maps
    shift_u, shift_v = np.ascontiguousarray(shift[:, 0]), np.ascontiguousarray(shift[:, 1])
    for rows in row_blocks(len(points)):
        block, block_chart = points[rows], chart[rows]
        block *= scale[block_chart][:, None, None]
        block[..., 0] += shift_u[block_chart][:, None]
        block[..., 1] += shift_v[block_chart][:, None]
    return points


def _adopt_orphans(mesh, topology, charts):
    """A chart for every triangle of a face in no chart: a charted neighbour's dominant chart.

    Returns ``(triangles, charts)`` as (k,) int64 arrays; a face with no
    charted neighbour takes chart 0 (it is too small to show anything).
    """
    dead_face = row_all(charts.chart_of_face < 0)
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
