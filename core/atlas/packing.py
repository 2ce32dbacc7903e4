"""Where every chart goes in the image, at one density: the rules of the layout.

At a density ``d`` (texels per object unit) a chart of extent ``e * d``
texels is one of three kinds:

``point``  under :data:`POINT_TEXELS` across (or no triangle with area): one
           texel, all its UVs at that texel's centre, where bilinear filtering
           reads that texel alone, so it needs no ring and no padding;
``small``  at most :data:`SMALL_TEXELS` across its narrow side: a slot of its
           whole-texel box plus the one-texel ring bilinear filtering reads on
           each side, shelf-packed (:mod:`.shelf`) with the points into square
           boxes (rows of thin rectangles pack far tighter than xatlas packs
           them: the 1:1000 beam's density went from 3.0 to 4.85 at 512²);
``large``  the rest: its coarse cover (:mod:`.cover`) goes to xatlas with the
           padding.

xatlas places the large covers and the boxes (no rotation, whole-texel
sizes, so every chart is only moved and keeps exactly ``d``).  A placement
that does not fit one image returns None; :func:`largest_density` searches
the largest density that fits.
"""

from dataclasses import dataclass

import numpy as np

from .cover import cover_at_density
from .settled_atlas import settled_atlas
from .shelf import shelf_pack

#: A chart less than this many texels across is stored as one texel.
POINT_TEXELS = 1.0
#: A chart at most this many texels across its narrow side is shelf-packed into a shared box.
SMALL_TEXELS = 6
#: The density search stops when the largest density known to fit and the
#: smallest known not to are this close (ratio).
DENSITY_TOLERANCE = 1.03
#: Padding shrinks while it would cost more than this share of extra atlas area.
PADDING_OVERHEAD = 0.10
#: Least xatlas padding between large charts: xatlas' own filtering margin alone was
#: measured to leave charts 1.35 texels apart, where bilinear filtering can read
#: a texel both charts reach; a padding of two keeps them 2+ texels apart.
MIN_PADDING = 2
#: Tolerated mismatch between xatlas' output and a pure translation, in texels.
AFFINE_TOLERANCE = 1e-2


def chart_kinds(extent, has_live, density):
    """(c,) int8: 0 point, 1 small, 2 large (see the module doc), for ``extent`` (c, 2) at ``density``."""
    texels = extent * density
    across = texels.max(axis=1)
    kind = np.where(texels.min(axis=1) <= SMALL_TEXELS, 1, 2).astype(np.int8)
    kind[(across < POINT_TEXELS) | ~has_live] = 0
    return kind


def xatlas_padding(free):
    """The xatlas padding that keeps at least ``free`` texels free between two large charts' rings.

    xatlas grows every chart by its padding ``q`` on each side before
    placing it, so the texels of two neighbouring charts (rings included)
    land ``2q`` apart, now and then ``2q - 1`` (tests/bench/bench_atlas_space.py
    measures it): at least ``2q - 2`` texels lie free between them.
    """
    return max(MIN_PADDING, -(-int(free) // 2) + 1)


def chart_footprints(extent, density, padding, has_live=None):
    """(c,) float64: texels each chart of ``extent`` (c, 2) object units takes at ``density``, as a box.

    Points take one texel, small charts ``(w + 2) * (h + 2)`` (whole-texel
    ``w, h`` and the filtering ring), large ones ``(w + 1 + 2q) * (h + 1 + 2q)``
    with their share of the ``2q - 1`` texels xatlas' padding ``q`` leaves
    between neighbours (:func:`xatlas_padding`).  Each is a whole number that
    never shrinks as the density grows.
    """
    has_live = np.ones(len(extent), dtype=bool) if has_live is None else has_live
    kind = chart_kinds(extent, has_live, density)
    size = np.maximum(np.ceil(extent * density - 1e-9), 1.0) + 2
    size[kind == 2] += 2 * padding - 1
    return np.where(kind > 0, size[:, 0] * size[:, 1], 1.0)


def footprint_texels(extent, density, padding, has_live=None):
    """Texels the charts of ``extent`` (c, 2) object units take at ``density``: the sum of
    :func:`chart_footprints` (whole numbers, so the sum is exact in any order)."""
    return float(chart_footprints(extent, density, padding, has_live).sum())


def effective_padding(extent, density, padding):
    """The xatlas padding to pack with: ``padding``, shrunk while it costs too much atlas area.

    :data:`MIN_PADDING` keeps bilinear filtering at one chart's rim from
    reading a texel of its neighbour; more keeps mip-maps (EEVEE at a
    distance) from mixing neighbouring charts.  The padding is the largest
    ``MIN_PADDING <= p <= padding`` for which the footprint
    (:func:`footprint_texels`) is at most ``1 + PADDING_OVERHEAD`` times the
    footprint at :data:`MIN_PADDING`.
    """
    limit = (1.0 + PADDING_OVERHEAD) * footprint_texels(extent, density, MIN_PADDING)
    p = max(int(padding), MIN_PADDING)
    while p > MIN_PADDING and footprint_texels(extent, density, p) > limit:
        p -= 1
    return p


def density_filling(extent, padding, texels, low, high):
    """Density in ``[low, high]`` whose footprint (:func:`footprint_texels`) is about ``texels``.

    The footprint grows with the density, so a bisection (in log density, 40
    halvings) finds it.  Each chart's footprint grows too, so a chart whose
    footprint is the same at both ends of the bracket keeps it inside: only
    the others are evaluated again, and after a few halvings they are a
    handful.  The sums are whole numbers, so every comparison, and the
    result, is the same as summing all charts at every step.
    """
    extent = np.asarray(extent, dtype=np.float64).reshape(-1, 2)
    at_low = chart_footprints(extent, low, padding)
    at_high = chart_footprints(extent, high, padding)
    settled = 0.0
    for _ in range(40):
        changing = at_low != at_high
        if not changing.all():
            settled += float(at_low[~changing].sum())
            extent, at_low, at_high = extent[changing], at_low[changing], at_high[changing]
        mid = np.sqrt(low * high)
        at_mid = chart_footprints(extent, mid, padding)
        if settled + float(at_mid.sum()) <= texels:
            low, at_low = mid, at_mid
        else:
            high, at_high = mid, at_mid
    return low


def largest_density(packer, image_size, area):
    """The placement at (nearly) the largest density whose charts fit one ``image_size`` image.

    Below ``all_points`` every chart is one texel, which fits by the choice
    of ``share``; above ``image_size / sqrt(area)`` the charts' area alone
    exceeds the image, and above ``fits_across`` the largest chart does.
    The first guess is where the footprint fills the image at the packing
    efficiency one xatlas run measures; from there the search walks in
    growing steps until the outcome flips, then bisects (in log density)
    until the bracket is within :data:`DENSITY_TOLERANCE`.

    Fitting is not quite monotone in the density (charts change kind at
    whole texels), so a bracket can close on a dip.  A look 6% above it
    fitted in 2 of 55 layouts of the test meshes, for one more xatlas run in
    most bakes (a tenth to a quarter of the search), and in none of the 12
    layouts of the four report meshes at 256², 512² and 1024²: it is not
    taken.
    """
    extent = packer.covers.extent
    share = packer.share_needed(image_size)
    largest = max(float(extent.max()), 1e-300)
    all_points = POINT_TEXELS / largest * 0.999
    fits_across = (image_size - 2 * (packer.padding + 3)) / largest
    low = all_points
    high = max(low, min(image_size / np.sqrt(max(area, 1e-300)), fits_across))
    if share > 1 or high <= low * DENSITY_TOLERANCE:
        return _all_points(packer, all_points, image_size, share)
    best = None                               # until a trial fits: every chart one texel (placed at the end)
    guess = density_filling(extent, packer.padding, image_size**2 * 0.8, low, high)
    probe = packer.place(guess, 0, share)
    efficiency = footprint_texels(extent, guess, packer.padding) / (probe.width * probe.height) if probe else 0.8
    trial = density_filling(extent, packer.padding, image_size**2 * min(efficiency, 1.0) * 0.98, low, high)
    step, walking, fitted_before = 1.03, True, None
    while high > low * DENSITY_TOLERANCE:
        if not low < trial < high:
            trial, walking = np.sqrt(low * high), False
        placement = packer.place(trial, image_size, share)
        fits = placement is not None
        if fits:
            best, low = placement, trial
        else:
            high = trial
        if walking and fitted_before is not None and fits != fitted_before:
            walking = False
        fitted_before = fits
        if walking:
            trial = trial * step if fits else trial / step
            step *= step
        else:
            trial = np.sqrt(low * high)
    return best if best is not None else _all_points(packer, all_points, image_size, share)


def _all_points(packer, all_points, image_size, share):
    """The placement with every chart one texel, ``share`` charts a texel (more if needed: never gives up)."""
    best = packer.place(all_points, image_size, share)
    while best is None:                       # cannot happen by the choice of share; never give up
        share *= 2
        best = packer.place(all_points, image_size, share)
    return best


class Packer:
    """Places charts at a given density (see the module doc).

    Parameters
    ----------
    covers : Covers
    centres : (c, 3) float64, a point of each chart in 3D (points that share a texel are neighbours)
    padding : int, texels between large charts (xatlas padding)
    """

    def __init__(self, covers, centres, padding):
        self.covers = covers
        self.centres = centres
        self.padding = int(padding)
        self.extent = covers.extent
        self.has_live = np.isfinite(covers.low[:, 0])

    def share_needed(self, image_size):
        """Charts per texel needed if every chart were one texel (1 unless there are more charts than room)."""
        room = max(1, image_size - 2 * (self.padding + 3)) ** 2
        return max(1, int(np.ceil(len(self.extent) / room)))

    def place(self, density, resolution, share):
        """A :class:`Placement` at ``density`` in a ``resolution`` image (0: as large as needed), or None."""
        import xatlas  # bundled wheel; imported here so the rest of core works without it

        count = len(self.extent)
        kind = chart_kinds(self.extent, self.has_live, density)
        large, small, points = (np.flatnonzero(kind == k) for k in (2, 1, 0))
        # slots: small charts with their ring, then one texel per `share` points
        small_size = np.maximum(np.ceil(self.extent[small] * density - 1e-9), 1).astype(np.int64) + 2
        point_order = points[spatial_order(self.centres[points])]
        point_slots = -(-len(points) // share)
        slot_w = np.concatenate([small_size[:, 0], np.ones(point_slots, dtype=np.int64)])
        slot_h = np.concatenate([small_size[:, 1], np.ones(point_slots, dtype=np.int64)])
        # one square box for all slots (shelves fill about 90% of it), or several as large as the image allows
        side = resolution or int(np.sqrt(footprint_texels(self.extent, density, self.padding)) + 1)
        slot_area = float((slot_w * slot_h).sum())
        box_side = int(max(SMALL_TEXELS + 2, min(np.ceil(np.sqrt(slot_area * 1.15)) + SMALL_TEXELS + 2,
                                                 side - 2 * (self.padding + 3) - 1)))
        shelves = shelf_pack(slot_w, slot_h, box_side)

        cover = cover_at_density(self.covers, large, density)
        vertices, indices, face_chart = cover.vertex_texel, cover.indices, cover.face_chart
        # each box as one rectangle, one texel larger than its content (see below)
        box_w, box_h = shelves.box_size[:, 0] + 1.0, shelves.box_size[:, 1] + 1.0
        zero = np.zeros(len(box_w))
        corners = np.stack([np.stack([zero, zero], 1), np.stack([box_w, zero], 1), np.stack([box_w, box_h], 1),
                            np.stack([zero, box_h], 1)], axis=1).reshape(-1, 2)
        first = len(vertices) + 4 * np.arange(len(box_w))
        indices = np.concatenate([indices, np.stack([first, first + 1, first + 2], 1),
                                  np.stack([first, first + 2, first + 3], 1)]).astype(np.int64)
        vertices = np.concatenate([vertices, corners])
        box_ids = count + np.arange(len(box_w))
        face_chart = np.concatenate([face_chart, box_ids, box_ids])

        with settled_atlas() as atlas:         # its destructor could hang were it let go of too soon
            atlas.add_uv_mesh(vertices.astype(np.float32), indices.astype(np.uint32),
                              face_chart[:, None].astype(np.uint32))
            options = xatlas.PackOptions()
            options.padding = self.padding
            options.bilinear = True
            options.rotate_charts = False
            options.rotate_charts_to_axis = False
            options.resolution = int(resolution)
            options.texels_per_unit = 1.0
            atlas.generate(xatlas.ChartOptions(), options)
            if atlas.atlas_count != 1:
                return None
            _, out_indices, out_uv = atlas[0]
            width, height = int(atlas.width), int(atlas.height)
        packed = out_uv.astype(np.float64)[out_indices.astype(np.int64)] * [width, height]
        shift = packed - vertices[indices]                                          # (f, 3, 2)
        # one translation per cover or box (xatlas neither rotates nor scales here: check)
        groups = count + len(box_w)
        weight = np.bincount(face_chart, minlength=groups) * 3.0
        offset = np.stack([np.bincount(np.repeat(face_chart, 3), shift[:, :, k].ravel(), groups)
                           for k in (0, 1)], axis=1) / np.maximum(weight, 1)[:, None]
        residual = np.abs(shift - offset[face_chart][:, None]).max() if len(shift) else 0.0
        if residual > AFFINE_TOLERANCE + 1e-6 * max(width, height):
            return None                     # xatlas shrank a chart that does not fit across: too dense
        if resolution:
            width = height = int(resolution)
        else:
            width, height = -(-width // 4) * 4, -(-height // 4) * 4

        # A box lands at a fractional corner; its content starts at the next whole texel,
        # still inside the rectangle xatlas reserved (one texel larger).
        box_origin = np.ceil(offset[count:] - 1e-6).astype(np.int64)                # (b, 2)
        slot_x = box_origin[shelves.box, 0] + shelves.x
        slot_y = box_origin[shelves.box, 1] + shelves.y
        origin = np.zeros((count, 2))
        chart_offset = offset[:count].copy()
        origin[large] = cover.origin
        # a small chart sits one texel (its ring) inside its slot, from its box's low corner
        origin[small] = self.covers.low[small]
        chart_offset[small] = np.stack([slot_x[:len(small)], slot_y[:len(small)]], 1) + 1.0
        point_texel = np.full(count, -1, dtype=np.int64)
        slot = np.arange(len(point_order)) // share + len(small)
        point_texel[point_order] = slot_y[slot] * width + slot_x[slot]
        return Placement(density=float(density), width=width, height=height, offset=chart_offset, origin=origin,
                         point_texel=point_texel, share=share, point_count=len(points), padding=self.padding)


@dataclass
class Placement:
    """Where every chart went: ``texel = density * (u - origin) + offset``, or one point texel."""

    density: float
    width: int
    height: int
    offset: np.ndarray          # (c, 2) texels
    origin: np.ndarray          # (c, 2) chart-plane point placed at ``offset``
    point_texel: np.ndarray     # (c,) flat texel of a one-texel chart, -1 for the others
    share: int                  # charts per point texel
    point_count: int
    padding: int

    def maps(self):
        """``(scale (c,), shift (c, 2))``: every chart's map chart plane -> texels, ``texel = scale * u + shift``
        (charts are never rotated; a point chart's scale is 0, its shift its texel's centre)."""
        drawn = self.point_texel < 0
        scale = np.where(drawn, float(self.density), 0.0)
        shift = np.empty((len(self.point_texel), 2))
        shift[drawn] = self.offset[drawn] - self.density * self.origin[drawn]
        texel = self.point_texel[~drawn]
        shift[~drawn, 0] = texel % self.width + 0.5
        shift[~drawn, 1] = texel // self.width + 0.5
        return scale, shift

    def warnings(self):
        """Sentences for the bake report."""
        if self.share <= 1:
            return []
        side = int(np.ceil(np.sqrt(self.point_count) + 2 * (self.padding + 3)))
        side = -(-side // 256) * 256
        return ["{:,} pieces are smaller than a texel and share texels ({} per texel); a {}x{} image would give "
                "each its own".format(self.point_count, self.share, side, side)]


def spatial_order(points):
    """Order of (k, 3) points along a Z-order (Morton) curve of their bounding box."""
    if len(points) < 2:
        return np.arange(len(points))
    low, high = points.min(axis=0), points.max(axis=0)
    cell = np.clip(((points - low) / np.maximum(high - low, 1e-300) * 1023).astype(np.int64), 0, 1023)
    code = np.zeros(len(points), dtype=np.int64)
    for bit in range(10):
        for axis in range(3):
            code |= ((cell[:, axis] >> bit) & 1) << (3 * bit + axis)
    return np.argsort(code, kind="stable")
