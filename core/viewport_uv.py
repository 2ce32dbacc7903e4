"""AO UVs for a surface other than the one baked: the viewport's, where a modifier such as Subdivision has
another level in the viewport than at render.

Within one chart the UVs are an affine function of the two coordinates the chart's axis keeps
(:meth:`.atlas.Atlas.layer_drop`), so each baked face carries, per layer, that function
(:func:`face_uv_maps`).  The ``Seamless AO`` modifier gives each face of the viewport's surface the function
of the baked face nearest to its centre and evaluates it at the face's own corners: one chart per face, so
no face spans two charts' texels.
"""

import numpy as np

#: The two coordinates a chart keeps, for each coordinate (0 x, 1 y, 2 z) it projects away.
KEPT = np.array([[1, 2], [0, 2], [0, 1]])
#: Relative to the mesh's size, the least spread of a face's corners the fit trusts in any direction:
#: along a direction where a face has less (it lies edge-on to its chart's plane) its map is flat.
RIDGE = 1.0e-6


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
        gradient = np.linalg.solve(spread, moment)                     # (f, 2 q, 2 uv)
        face_kept = kept[loop_start]
        for row in range(2):
            np.put_along_axis(linear[layer, :, row], face_kept, gradient[:, :, row].astype(np.float32), axis=1)
        offset[layer] = uv_mean - np.einsum("fq,fqr->fr", q_mean, gradient)
    return linear, offset
