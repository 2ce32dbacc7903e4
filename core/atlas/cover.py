"""Coarse covers of charts: what the packer needs to know of a chart's shape.

A packer only needs each chart's footprint, not its triangles.  A chart is
cut into ``rows`` horizontal bands of equal height in its plane; in each band
the exact x-extent of the chart's triangles clipped to the band is kept.  The
cover is a strip of trapezoids through those bands: it contains every
triangle of the chart, is one connected piece (so a packer keeps it as one
chart), and has ``2 * rows`` triangles however many the chart has.  Bands are
in chart-plane units, so the same cover serves every trial density of a
density search; :func:`cover_at_density` only scales it.
"""

from dataclasses import dataclass

import numpy as np

from ..arrays.geometry2d import band_x_extent, corner_max, corner_min
from ..arrays.graph import index_in_runs

#: Most bands per chart (a chart's cover has twice as many triangles).
MAX_ROWS = 32
#: Height of one band at the expected density, in texels.
ROW_TEXELS = 2.0


@dataclass
class Covers:
    """Row bands of every chart, in chart-plane units.

    Attributes
    ----------
    low, high : (c, 2) float64
        Bounding box of each chart's live triangles (``inf`` / ``-inf`` for a
        chart with none).
    rows : (c,) int64
        Bands per chart (at least 1).
    first_row : (c,) int64
        Index of each chart's first band in ``x_low`` / ``x_high``.
    x_low, x_high : (r,) float64
        x-extent of each band (all bands of chart 0, then chart 1, ...).
    """

    low: np.ndarray
    high: np.ndarray
    rows: np.ndarray
    first_row: np.ndarray
    x_low: np.ndarray
    x_high: np.ndarray

    @property
    def extent(self):
        """(c, 2) width and height of each chart (0 for a chart with no live triangle)."""
        return np.where(np.isfinite(self.low), self.high - self.low, 0.0)


def _group_extreme(ufunc, values, group, count):
    """(count,) float64: ``ufunc`` of ``values`` (m,) over each group (``inf`` or ``-inf`` for an empty one)."""
    out = np.full(count, np.inf if ufunc is np.minimum else -np.inf)
    ufunc.at(out, group, values)
    return out


def chart_covers(local_uv, member_chart, chart_count, expected_density):
    """Row bands of every chart.

    Parameters
    ----------
    local_uv : (m, 3, 2) float64
        Live (non-degenerate) members' corners in their chart's plane.
    member_chart : (m,) int
        Chart of each member.
    chart_count : int
    expected_density : float
        Texels per object unit the layout is expected near; bands are about
        :data:`ROW_TEXELS` high at that density, at most :data:`MAX_ROWS`.

    Returns
    -------
    Covers
    """
    member_chart = np.asarray(member_chart, dtype=np.int64)
    # each member's box, once, a coordinate at a time into contiguous columns (every pass below reads them
    # whole): the charts' boxes, the bands and whole triangles' x-extents all read it
    member_low = [corner_min(local_uv[..., axis]).ravel() for axis in range(2)]          # x, y (m,) each
    member_high = [corner_max(local_uv[..., axis]).ravel() for axis in range(2)]
    low = np.stack([_group_extreme(np.minimum, column, member_chart, chart_count) for column in member_low], axis=1)
    high = np.stack([_group_extreme(np.maximum, column, member_chart, chart_count) for column in member_high],
                    axis=1)
    height = np.where(np.isfinite(low[:, 1]), high[:, 1] - low[:, 1], 0.0)
    rows = np.clip(np.ceil(height * expected_density / ROW_TEXELS), 1, MAX_ROWS).astype(np.int64)
    first_row = np.concatenate([[0], np.cumsum(rows)[:-1]])
    band = np.where(height > 0, height / rows, 1.0)                          # (c,) band height

    # one more band at the end, where the triangles clipped band by band go in the pass over whole ones
    x_low = np.full(int(rows.sum()) + 1, np.inf)
    x_high = np.full(int(rows.sum()) + 1, -np.inf)
    # the band of each member's lowest and highest point
    chart_low_y, chart_band = low[member_chart, 1], band[member_chart]
    last = rows[member_chart] - 1
    r0 = np.clip(np.floor((member_low[1] - chart_low_y) / chart_band), 0, last).astype(np.int64)
    r1 = np.clip(np.floor((member_high[1] - chart_low_y) / chart_band), 0, last).astype(np.int64)
    del chart_low_y, chart_band
    # A triangle touching one or two bands adds its own x-extent to each (conservative by less
    # than its width), straight from its box; only triangles spanning more bands are clipped to each
    # band exactly, one (member, band) pair at a time.
    long = np.flatnonzero(r1 - r0 > 1)
    key = first_row[member_chart] + r0
    key[long] = len(x_low) - 1
    np.minimum.at(x_low, key, member_low[0])
    np.maximum.at(x_high, key, member_high[0])
    # the second band, where it is another one (a triangle far smaller than a band mostly lies in one)
    second = np.flatnonzero(r1 - r0 == 1)
    key = key[second] + 1
    np.minimum.at(x_low, key, member_low[0][second])
    np.maximum.at(x_high, key, member_high[0][second])
    x_low, x_high = x_low[:-1], x_high[:-1]
    del key, second, member_low, member_high
    count = r1[long] - r0[long] + 1
    pair_member = np.repeat(long, count)
    pair_row = np.repeat(r0[long], count) + index_in_runs(count)
    pair_chart = member_chart[pair_member]
    band_low = low[pair_chart, 1] + pair_row * band[pair_chart]
    band_high = band_low + band[pair_chart]
    # the first and last band reach past the chart's bounds (no rounding gap)
    reach = band[pair_chart]
    band_low = np.where(pair_row == 0, band_low - reach, band_low)
    band_high = np.where(pair_row == last[pair_member], band_high + reach, band_high)
    x0, x1 = band_x_extent(local_uv[pair_member], band_low, band_high)
    key = first_row[pair_chart] + pair_row
    np.minimum.at(x_low, key, x0)
    np.maximum.at(x_high, key, x1)
    # a band no triangle reaches (a gap in the chart's projection): the chart's whole width
    chart_of_row = np.repeat(np.arange(chart_count), rows)
    empty = x_low > x_high
    x_low[empty] = np.where(np.isfinite(low[chart_of_row[empty], 0]), low[chart_of_row[empty], 0], 0.0)
    x_high[empty] = np.where(np.isfinite(high[chart_of_row[empty], 0]), high[chart_of_row[empty], 0], 0.0)
    return Covers(low=low, high=high, rows=rows, first_row=first_row, x_low=x_low, x_high=x_high)


@dataclass
class CoverMesh:
    """Covers of some charts at one density, as a packer's input."""

    vertex_texel: np.ndarray   # (v, 2) float64, texels from each cover's own corner
    indices: np.ndarray        # (f, 3) int64
    face_chart: np.ndarray     # (f,) int64
    origin: np.ndarray         # (k, 2) float64, chart-plane point at each cover's corner (texel 0, 0)


def cover_at_density(covers, charts, density, min_texels=1.0):
    """Trapezoid strips of ``charts`` at ``density``, each at least ``min_texels`` wide and high.

    Each cover starts at texel (0, 0) and its width and height are whole
    texels (its right-most and top-most points pushed out to the next
    integer): xatlas stretches a chart to whole texels, and a cover that
    already is one is only moved, so every chart keeps exactly ``density``.

    Parameters
    ----------
    covers : Covers
    charts : (k,) int, charts to include (each must have a live triangle)
    density : float, texels per object unit
    min_texels : float
        Thinner covers are widened about their centre line, so a packer
        never drops one as degenerate.

    Returns
    -------
    CoverMesh
    """
    charts = np.asarray(charts, dtype=np.int64)
    rows = covers.rows[charts]
    lines = rows + 1
    line_chart = np.repeat(charts, lines)
    line_index = index_in_runs(lines)
    row_count = covers.rows[line_chart]
    first = covers.first_row[line_chart]
    # boundary line k joins bands k-1 and k: its extent is the union of both
    below = first + np.clip(line_index - 1, 0, row_count - 1)
    above = first + np.clip(line_index, 0, row_count - 1)
    x_low = np.minimum(covers.x_low[below], covers.x_low[above])
    x_high = np.maximum(covers.x_high[below], covers.x_high[above])
    low, high = covers.low[line_chart], covers.high[line_chart]
    y = low[:, 1] + (high[:, 1] - low[:, 1]) * line_index / row_count

    # to texels from the chart's low corner, widened to ``min_texels``
    tx_low, tx_high = (x_low - low[:, 0]) * density, (x_high - low[:, 0]) * density
    grow = np.maximum(0.0, min_texels - (tx_high - tx_low)) * 0.5
    tx_low, tx_high = tx_low - grow, tx_high + grow
    ty = (y - low[:, 1]) * density
    chart_height = (high[:, 1] - low[:, 1]) * density
    stretch = np.maximum(1.0, min_texels / np.maximum(chart_height, 1e-300))
    ty = 0.5 * chart_height + (ty - 0.5 * chart_height) * stretch
    # each cover from texel (0, 0) to whole texels (w, h)
    line_of = np.repeat(np.arange(len(charts)), lines)
    corner = np.stack([np.full(len(charts), np.inf), np.full(len(charts), np.inf)], axis=1)
    np.minimum.at(corner[:, 0], line_of, tx_low)
    np.minimum.at(corner[:, 1], line_of, ty)
    tx_low, tx_high, ty = tx_low - corner[line_of, 0], tx_high - corner[line_of, 0], ty - corner[line_of, 1]
    right = np.zeros(len(charts))
    np.maximum.at(right, line_of, tx_high)
    top = np.zeros(len(charts))
    np.maximum.at(top, line_of, ty)
    tx_high = np.where(tx_high >= right[line_of], np.ceil(right[line_of] - 1e-9), tx_high)
    ty = np.where(ty >= top[line_of], np.ceil(top[line_of] - 1e-9), ty)
    texel = np.stack([np.stack([tx_low, ty], -1), np.stack([tx_high, ty], -1)], axis=1).reshape(-1, 2)
    origin = covers.low[charts] + corner / density

    # two triangles per band: lines k and k+1 of the same chart
    line_start = np.repeat(np.cumsum(lines) - lines, rows) * 2
    band_index = index_in_runs(rows)
    a = line_start + 2 * band_index          # bottom-left; +1 bottom-right; +2 top-left; +3 top-right
    indices = np.concatenate([np.stack([a, a + 1, a + 3], 1), np.stack([a, a + 3, a + 2], 1)])
    face_chart = np.concatenate([np.repeat(charts, rows)] * 2)
    return CoverMesh(vertex_texel=texel, indices=indices, face_chart=face_chart, origin=origin)
