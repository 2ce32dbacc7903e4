"""AO UVs for a surface other than the one baked: the viewport's, where a modifier such as Subdivision has
another level in the viewport than at render.

Within one chart the UVs are an affine function of the two coordinates the chart's axis keeps
(:meth:`.chart_atlas.Atlas.layer_drop`), so each baked face carries, per layer, that function
(:func:`face_uv_maps`).  :func:`surface_uv` gives each face of the other surface, per layer, one chart's
function evaluated at its own corners: the chart of the baked face nearest its centre, or, where the face
reaches past that chart, the chart that holds most of its corners.  A corner the chosen chart does not hold
reads the chart's edge nearest it instead of whatever lies past that edge in the image (another chart, or
nothing).
"""

import numpy as np

#: The two coordinates a chart keeps, for each coordinate (0 x, 1 y, 2 z) it projects away.
KEPT = np.array([[1, 2], [0, 2], [0, 1]])
#: Relative to the mesh's size, the least spread of a face's corners the fit trusts in any direction:
#: along a direction where a face has less (it lies edge-on to its chart's plane) its map is flat.
RIDGE = 1.0e-6


def _solve_2x2(matrix, right):
    """``np.linalg.solve`` for many 2x2 systems (f, 2, 2) by the closed form, in a fraction of its time
    (``matrix`` symmetric positive definite here: a spread plus a ridge)."""
    a, b, c, d = matrix[:, 0, 0], matrix[:, 0, 1], matrix[:, 1, 0], matrix[:, 1, 1]
    determinant = (a * d - b * c)[:, None, None]
    inverse = np.stack([np.stack([d, -b], axis=1), np.stack([-c, a], axis=1)], axis=1) / determinant
    return np.einsum("fij,fjk->fik", inverse, right)


def face_uv_maps(positions, corner_vert, loop_start, corner_uv, corner_drop):
    """Per face and layer, the affine map from a position to its UV in that layer.

    Parameters
    ----------
    positions : (v, 3) float, object space
    corner_vert : (l,) int, each corner's vertex
    loop_start : (f,) int, ascending: face ``i`` has corners ``loop_start[i]`` up to the next face's first
    corner_uv : (3 layers, l, 2) float, each corner's UV in AO_X, AO_Y, AO_Z
    corner_drop : (3 layers, l) int, the coordinate the corner's chart projects away in each layer (the same
        for every corner of a face)

    Returns
    -------
    linear : (3 layers, f, 2, 3) float32
        ``uv = linear @ position + offset``; the dropped coordinate's column is 0
    offset : (3 layers, f, 2) float32
    """
    positions = np.asarray(positions, dtype=np.float64)
    loop_start = np.asarray(loop_start, dtype=np.int64)
    corner_count = len(corner_vert)
    sizes = np.diff(np.append(loop_start, corner_count))
    face_of_corner = np.repeat(np.arange(len(loop_start)), sizes)
    corner_position = positions[corner_vert]
    scale = float(np.ptp(positions, axis=0).max()) if len(positions) else 1.0
    ridge = (RIDGE * max(scale, 1e-30)) ** 2
    layers = len(corner_uv)
    linear = np.zeros((layers, len(loop_start), 2, 3), dtype=np.float32)
    offset = np.zeros((layers, len(loop_start), 2), dtype=np.float32)

    def face_mean(values):
        return np.add.reduceat(values, loop_start, axis=0) / sizes.reshape((-1,) + (1,) * (values.ndim - 1))

    for layer in range(layers):
        drop = np.asarray(corner_drop[layer], dtype=np.int64)
        kept = KEPT[drop]                                              # (l, 2)
        q = np.take_along_axis(corner_position, kept, axis=1)          # (l, 2) the chart's plane coordinates
        uv = np.asarray(corner_uv[layer], dtype=np.float64)
        q_mean, uv_mean = face_mean(q), face_mean(uv)
        dq = q - q_mean[face_of_corner]
        duv = uv - uv_mean[face_of_corner]
        spread = np.add.reduceat(dq[:, :, None] * dq[:, None, :], loop_start, axis=0)      # (f, 2, 2)
        spread += ridge * np.eye(2)
        moment = np.add.reduceat(dq[:, :, None] * duv[:, None, :], loop_start, axis=0)     # (f, 2, 2): q by uv
        gradient = _solve_2x2(spread, moment)                          # (f, 2 q, 2 uv)
        face_kept = kept[loop_start]
        for row in range(2):
            np.put_along_axis(linear[layer, :, row], face_kept, gradient[:, :, row].astype(np.float32), axis=1)
        offset[layer] = uv_mean - np.einsum("fq,fqr->fr", q_mean, gradient)
    return linear, offset


#: Where the 90th percentile of the distance from the viewport surface's vertices to the baked surface is more
#: than this share of the baked surface's bounding-box diagonal, the viewport surface stands off it (a
#: Subdivision cage does: 1.26% on Suzanne, docs/bench/bench_viewport.md; a surface of level 1 or more has
#: its vertices on the next level's) and no AO read from the baked surface can be its own: it is baked too
#: (:func:`stands_off`).
STANDOFF = 1.0e-3
#: A corner is held by a chart where that chart's map and the map of the baked face nearest the corner agree
#: to within this many texels (two charts put one point hundreds of texels apart).
AGREE_TEXELS = 1.5
#: Halvings of the segment from a face's centre to a corner its chart does not hold, in search of the chart's edge.
EDGE_STEPS = 8


class NearestTriangle:
    """The triangle of a mesh nearest a point, through mathutils' BVH."""

    def __init__(self, positions, triangles):
        from mathutils.bvhtree import BVHTree
        self.tree = BVHTree.FromPolygons(np.asarray(positions, dtype=np.float64).tolist(),
                                         np.asarray(triangles).tolist(), all_triangles=True)

    def __call__(self, points):
        """The triangle nearest each of ``points`` (k, 3) (a loop over the BVH), and the nearest point on it.

        Returns
        -------
        triangles : (k,) int
        nearest : (k, 3) float64
        """
        points = np.asarray(points, dtype=np.float64)
        found, nearest = np.zeros(len(points), dtype=np.int64), points.copy()
        for k, point in enumerate(points.tolist()):
            location, _, index, _ = self.tree.find_nearest(point)
            if index is not None:
                found[k], nearest[k] = index, location
        return found, nearest


def stands_off(baked_positions, baked_triangles, points):
    """Whether ``points`` (k, 3) (a surface's vertices) stand off the surface of triangles ``baked_triangles``
    (t, 3) over ``baked_positions`` (v, 3) by more than :data:`STANDOFF` of its diagonal, at the 90th
    percentile of their distances to it."""
    if not len(points) or not len(baked_triangles):
        return False
    points = np.asarray(points, dtype=np.float64)
    distance = np.linalg.norm(NearestTriangle(baked_positions, baked_triangles)(points)[1] - points, axis=1)
    diagonal = float(np.linalg.norm(np.ptp(np.asarray(baked_positions, dtype=np.float64), axis=0)))
    return bool(np.percentile(distance, 90) > STANDOFF * max(diagonal, 1e-30))


class _LayerMaps:
    """One layer's per-face maps, and whether a chart holds a point."""

    def __init__(self, linear, offset, texel):
        self.linear, self.offset, self.texel = linear.astype(np.float64), offset.astype(np.float64), texel

    def uv(self, faces, points):
        """(k, 2): UV of ``points`` (k, 3) through the maps of ``faces`` (k,)."""
        return np.einsum("krc,kc->kr", self.linear[faces], points) + self.offset[faces]

    def holds(self, faces, near, points):
        """(k,) bool: the chart of ``faces`` holds ``points``, whose nearest baked faces are ``near``: the two
        maps agree there."""
        gap = np.abs(self.uv(faces, points) - self.uv(near, points)) / self.texel
        return (gap <= AGREE_TEXELS).all(axis=1)


def _corner_table(loop_start, sizes):
    """(f, most corners) corner of each face's slot, and (f, most corners) bool: the slot is a corner."""
    slots = np.arange(max(int(sizes.max(initial=0)), 1))
    valid = slots[None, :] < sizes[:, None]
    return np.where(valid, loop_start[:, None] + slots[None, :], loop_start[:, None]), valid


def _best_charts(maps, centre_near, corner_near, corner_position, table, valid):
    """(s,) per face (rows of ``table``/``valid``): the baked face whose chart holds most of its corners,
    among its centre's nearest face's and its corners' (the centre's on a tie)."""
    candidates = np.concatenate([centre_near[:, None], corner_near[table]], axis=1)         # (s, k)
    shape = (len(table), candidates.shape[1], table.shape[1])
    corners = np.broadcast_to(table[:, None, :], shape).ravel()
    held = maps.holds(np.broadcast_to(candidates[:, :, None], shape).ravel(), corner_near[corners],
                      corner_position[corners]).reshape(shape) & valid[:, None, :]
    return candidates[np.arange(len(table)), np.argmax(held.sum(axis=2), axis=1)]   # argmax: the first


def _edge_towards(maps, chart_face, inside, outside, nearest):
    """Per row, the point between ``inside`` (k, 3) (held by the chart of ``chart_face`` (k,)) and ``outside``
    (not held) where the chart's edge lies, to within 2^-EDGE_STEPS of the segment."""
    for _ in range(EDGE_STEPS):
        middle = 0.5 * (inside + outside)
        held = maps.holds(chart_face, nearest(middle)[0], middle)[:, None]
        inside, outside = np.where(held, middle, inside), np.where(held, outside, middle)
    return inside


def surface_uv(baked, baked_uv, baked_drop, shown, image_size):
    """Per layer, UVs for the corners of another surface near the baked one (the viewport's, at other
    Subdivision levels).

    Parameters
    ----------
    baked : (positions (v, 3) float, triangles (t, 3) int) of the baked surface
    baked_uv : (3 layers, t, 3 corners, 2) float, the baked triangles' UVs in AO_X, AO_Y, AO_Z
    baked_drop : (t, 3 layers) int, the coordinate each baked triangle's chart projects away in each layer
    shown : (positions (v, 3) float, corner_vert (l,) int, loop_start (f,) int) of the surface to give UVs,
        in the baked surface's object space
    image_size : (width, height) in texels

    Returns
    -------
    (3 layers, l shown corners, 2) float32 in [0, 1]
    """
    positions, triangles = (np.asarray(a) for a in baked)
    corner_drop = np.repeat(np.asarray(baked_drop).T, 3, axis=1)                  # (3 layers, 3t)
    linear, offset = face_uv_maps(positions, triangles.ravel(), np.arange(len(triangles)) * 3,
                                  np.asarray(baked_uv).reshape(3, -1, 2), corner_drop)
    nearest = NearestTriangle(positions, triangles)
    positions = np.asarray(shown[0], dtype=np.float64)
    corner_vert, loop_start = np.asarray(shown[1], dtype=np.int64), np.asarray(shown[2], dtype=np.int64)
    sizes = np.diff(np.append(loop_start, len(corner_vert)))
    face_of_corner = np.repeat(np.arange(len(loop_start)), sizes)
    corner_position = positions[corner_vert]
    centre = np.add.reduceat(corner_position, loop_start, axis=0) / np.maximum(sizes, 1)[:, None] \
        if len(loop_start) else np.zeros((0, 3))
    found, _ = nearest(np.concatenate([positions, centre]))
    corner_near, centre_near = found[:len(positions)][corner_vert], found[len(positions):]
    table, valid = _corner_table(loop_start, sizes)
    texel = 1.0 / np.asarray(image_size, dtype=np.float64)
    out = np.zeros((3, len(corner_vert), 2), dtype=np.float32)
    for layer in range(3):
        maps = _LayerMaps(linear[layer], offset[layer], texel)
        chart_face = centre_near[face_of_corner]
        held = maps.holds(chart_face, corner_near, corner_position)
        reaching = np.unique(face_of_corner[~held])          # faces that reach past their centre's chart
        best = _best_charts(maps, centre_near[reaching], corner_near, corner_position, table[reaching],
                            valid[reaching])
        corners = table[reaching][valid[reaching]]            # their corners, face by face
        owner = np.repeat(np.arange(len(reaching)), sizes[reaching])
        chart_face[corners] = best[owner]
        held[corners] = maps.holds(chart_face[corners], corner_near[corners], corner_position[corners])
        uv = maps.uv(chart_face, corner_position)
        # a corner past its face's chart reads the chart's edge, found from the held corners' centre
        held_sum = np.zeros((len(reaching), 3))
        np.add.at(held_sum, owner[held[corners]], corner_position[corners[held[corners]]])
        count = np.bincount(owner[held[corners]], minlength=len(reaching))[:, None]
        inside = np.where(count > 0, held_sum / np.maximum(count, 1), centre[reaching])
        past = corners[~held[corners]]
        edge = _edge_towards(maps, chart_face[past], inside[owner[~held[corners]]], corner_position[past], nearest)
        uv[past] = maps.uv(chart_face[past], edge)
        out[layer] = np.clip(np.nan_to_num(uv, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    return out
