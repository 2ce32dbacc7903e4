"""How large a mesh is: the box its tolerances and its rays' float32 space follow, a stray spike left out.

Every tolerance of the core (welding, zero area, injectivity, rim inset, the
ray origins' lift) is relative to the mesh's size; one spike to a vertex far
out must not set it (:func:`robust_box`).
"""

import numpy as np

from ..arrays.reduce import column_max, column_min

#: The size that sets the tolerances leaves out the triangles reaching far out of the rest of the mesh
#: (:func:`robust_box`) if they are at most this share of the triangles (or :data:`STRAY_LEAST`) ...
OUTLIER_SHARE = 1.0e-3
STRAY_LEAST = 16
#: ... and the whole box is more than this many times larger than the rest (a spike to a stray vertex).
OUTLIER_RATIO = 10.0
#: The rest: the vertices without this share of them (at least :data:`TRIM_LEAST`, the corners of
#: :data:`STRAY_LEAST` triangles) at each end of each axis.
TRIM_SHARE = 0.01
TRIM_LEAST = 3 * STRAY_LEAST
#: A mesh with fewer triangles than this keeps its whole box: its stray triangles could not be few.
ROBUST_LEAST_TRIANGLES = 1000


def mesh_size(positions):
    """Bounding-box diagonal of ``positions`` (v, 3); 1.0 for an empty or point-like set."""
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    if not len(positions):
        return 1.0
    size = float(np.linalg.norm(column_max(positions) - column_min(positions)))
    return size if size > 0.0 else 1.0


def robust_box(positions, triangles):
    """``(low, high, stray)``: the bounding box (3,) float64 of the vertices ``triangles`` (t, 3) use of
    ``positions`` (v, 3), without the few triangles that reach far out, if there are such (``stray`` (t,) bool).

    Triangles reach far out when they have a vertex outside the box of the
    rest (the vertices without the :data:`TRIM_SHARE` at each end of each
    axis) grown by that box's diagonal on every side.  They are left out
    when the mesh has :data:`ROBUST_LEAST_TRIANGLES` or more, they are at most
    :data:`OUTLIER_SHARE` of them (or :data:`STRAY_LEAST`, if more) and the
    whole box is more than :data:`OUTLIER_RATIO` times larger than the rest:
    a spike to a stray vertex, or a few triangles floating far off, never a
    cone's long tip, whose triangles are many.  Otherwise a scan with one
    spike to a vertex 10,000 units out would weld (and call zero-area)
    whatever lies within a hundredth of a unit, and cast its rays from
    float32 positions 5,000 units from the box's centre.
    """
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    used = np.zeros(len(positions), dtype=bool)
    used[triangles.ravel()] = True
    points = positions[used]
    none = np.zeros(len(triangles), dtype=bool)
    if not len(points):
        return np.zeros(3), np.zeros(3), none
    low, high = column_min(points), column_max(points)
    if len(triangles) < ROBUST_LEAST_TRIANGLES:
        return low, high, none
    trim = min(max(TRIM_LEAST, int(len(points) * TRIM_SHARE)), (len(points) - 1) // 4)
    ends = np.partition(points, (trim, len(points) - 1 - trim), axis=0)
    inner_low, inner_high = ends[trim], ends[len(points) - 1 - trim]
    reach = float(np.linalg.norm(inner_high - inner_low))
    if not np.linalg.norm(high - low) > OUTLIER_RATIO * reach:
        return low, high, none
    outside = ((positions < inner_low - reach) | (positions > inner_high + reach)).any(axis=1)
    stray = outside[triangles].any(axis=1)
    if stray.sum() > max(OUTLIER_SHARE * len(triangles), STRAY_LEAST) or stray.all():
        return low, high, none
    kept = positions[triangles[~stray]].reshape(-1, 3)
    return column_min(kept), column_max(kept), stray


def box_size(low, high):
    """Diagonal of the box ``low``, ``high`` (3,); 1.0 for a point (the size tolerances are relative to)."""
    size = float(np.linalg.norm(np.asarray(high) - np.asarray(low)))
    return size if size > 0.0 else 1.0
