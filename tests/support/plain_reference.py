"""A plain AO reference that shares no code with the baker.

Plain ``mathutils.bvhtree.BVHTree.ray_cast`` in a Python loop; numpy
pseudo-random cosine-distributed directions around the interpolated shading
normal; the origin lifted along the geometric normal; a hit closer than the
maximum distance occludes fully.  Nothing else: no Sobol' points, no
mirroring of rays below the face, no stepping through back faces.
"""

import numpy as np
from mathutils import Vector
from mathutils.bvhtree import BVHTree

#: Origin lift along the geometric normal, relative to the mesh's bounding-box diagonal.
LIFT = 1e-5
#: A point some piece winds around more than this is inside it (1 inside a closed piece, 0 outside,
#: below 1/2 behind an open sheet such as a drape before a wall).
INSIDE_WINDING = 0.6


def plain_ao(positions, triangles, points, shading, geometric, max_distance, rays=4096, seed=0):
    """AO (1 open, 0 blocked) at ``points`` (k, 3), binary hits within ``max_distance``.

    ``shading`` and ``geometric`` are (k, 3) unit normals; ``positions`` (v, 3) and
    ``triangles`` (t, 3) are the occluders, in the same space as the points.
    """
    positions = np.asarray(positions, dtype=np.float64)
    tree = BVHTree.FromPolygons(positions.tolist(), np.asarray(triangles).tolist(), all_triangles=True)
    lift = LIFT * float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0)))
    rng = np.random.default_rng(seed)
    out = np.empty(len(points))
    for k, (point, normal, face_normal) in enumerate(zip(points, shading, geometric)):
        tangent, bitangent = _frame(normal)
        u1, u2 = rng.random(rays), rng.random(rays)
        radius, angle = np.sqrt(u1), 2.0 * np.pi * u2
        directions = (np.outer(radius * np.cos(angle), tangent) + np.outer(radius * np.sin(angle), bitangent)
                      + np.outer(np.sqrt(1.0 - u1), normal))
        origin = Vector((point + lift * face_normal).tolist())
        blocked = sum(tree.ray_cast(origin, Vector(d), max_distance)[0] is not None for d in directions.tolist())
        out[k] = 1.0 - blocked / rays
    return out


def visible_points(positions, triangles, count, seed=0, tolerance=1e-6):
    """Area-weighted random surface points, leaving out points that lie on an opposite-facing surface.

    A point on a crate's bottom lies on the floor it stands on: it is never
    seen, and its AO depends on how coincident surfaces are treated.  Each
    point is tested alone (not its triangle's centre), so a floor partly
    under a crate keeps its visible part.

    Returns triangle (k,), bary (k, 3), points (k, 3).
    """
    positions = np.asarray(positions, dtype=np.float64)
    triangles = np.asarray(triangles)
    corners = positions[triangles]
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    rng = np.random.default_rng(seed)
    chosen, weights, found = [], [], []
    while len(found) < count:
        triangle = rng.choice(len(area), size=count, p=area / area.sum())
        r1, r2 = rng.random(count), rng.random(count)
        s = np.sqrt(r1)
        bary = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)
        points = np.einsum("kc,kcd->kd", bary, corners[triangle])
        seen = ~hidden(positions, triangles, triangle, points, tolerance)
        chosen.append(triangle[seen]), weights.append(bary[seen]), found.extend(points[seen])
    return np.concatenate(chosen)[:count], np.concatenate(weights)[:count], np.array(found[:count])


def hidden(positions, triangles, triangle, points, tolerance=1e-6):
    """(k,) bool: whether each point (k, 3) of ``triangle`` (k,) can never be seen.

    A point is hidden when it lies on another, opposite-facing triangle (within
    ``tolerance`` of the bounding-box diagonal: a crate's bottom on the floor), or
    inside another closed piece (a crate's corner inside the crate it overlaps,
    the part of Suzanne's head inside her eyeball): every one of a few rays into
    its hemisphere first meets the back of a face, or, lifted off its face, some
    piece winds around it more than :data:`INSIDE_WINDING` times
    (:func:`largest_piece_winding`: Suzanne's eyes are open shells, which the
    rays miss).
    """
    positions = np.asarray(positions, dtype=np.float64)
    triangles = np.asarray(triangles)
    corners = positions[triangles]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normal = cross / np.maximum(np.linalg.norm(cross, axis=1), 1e-300)[:, None]
    tree = BVHTree.FromPolygons(positions.tolist(), triangles.tolist(), all_triangles=True)
    diagonal = float(np.linalg.norm(positions.max(axis=0) - positions.min(axis=0)))
    radius = tolerance * diagonal
    out = np.zeros(len(points), dtype=bool)
    for k, (t, p) in enumerate(zip(np.asarray(triangle).tolist(), np.asarray(points).tolist())):
        own = Vector(normal[t].tolist())
        out[k] = (any(n.dot(own) < -0.99 for _, n, other, _ in tree.find_nearest_range(Vector(p), radius)
                      if other != t)
                  or _enclosed(tree, np.asarray(p) + LIFT * diagonal * normal[t], normal[t]))
    lifted = np.asarray(points, dtype=np.float64) + LIFT * diagonal * normal[np.asarray(triangle)]
    return out | (largest_piece_winding(positions, triangles, lifted) > INSIDE_WINDING)


def winding_numbers(corners, points):
    """Generalised winding number (k,) of the triangles ``corners`` (t, 3, 3) around ``points`` (k, 3).

    The signed solid angle of each triangle seen from the point (Van Oosterom
    and Strackee's formula), summed and divided by 4 pi: 1 inside a closed,
    outward-facing surface, 0 outside it, 1/2 on it.
    """
    out = np.zeros(len(points))
    step = max(1, 2_000_000 // max(len(corners), 1))
    for start in range(0, len(points), step):
        a, b, c = (corners[None, :, j] - points[start:start + step, None] for j in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=2) for v in (a, b, c))
        numerator = np.einsum("ktd,ktd->kt", a, np.cross(b, c))
        denominator = (la * lb * lc + np.einsum("ktd,ktd->kt", a, b) * lc + np.einsum("ktd,ktd->kt", b, c) * la
                       + np.einsum("ktd,ktd->kt", c, a) * lb)
        out[start:start + step] = 2.0 * np.arctan2(numerator, denominator).sum(axis=1) / (4.0 * np.pi)
    return out


def pieces(positions, triangles):
    """(t,) int: the connected piece of each triangle (triangles with a vertex at the same position are
    one piece: a box built of six separate grids is one piece)."""
    _, same = np.unique(np.asarray(positions, dtype=np.float64), axis=0, return_inverse=True)
    triangles = same.reshape(-1)[np.asarray(triangles)]
    label = np.arange(triangles.max() + 1 if len(triangles) else 0)
    while True:
        smallest = label[triangles].min(axis=1)
        before = label.copy()
        for c in range(3):
            np.minimum.at(label, triangles[:, c], smallest)
        label = label[label]                                            # jump along the chains
        if np.array_equal(label, before):
            return np.unique(label[triangles[:, 0]], return_inverse=True)[1].reshape(-1)


def largest_piece_winding(positions, triangles, points):
    """(k,) the largest winding number of any one piece (:func:`pieces`) around each point (k, 3).

    Pieces one by one, not the whole mesh: a room's walls face inward and
    would cancel the 1 of a block standing inside it.  Only pieces whose
    bounding box holds the point are asked: from outside its box a piece lies
    in a half-space and winds at most 1/2 around the point.
    """
    positions = np.asarray(positions, dtype=np.float64)
    triangles = np.asarray(triangles)
    points = np.asarray(points, dtype=np.float64)
    piece = pieces(positions, triangles)
    out = np.zeros(len(points))
    for p in range(piece.max() + 1 if len(piece) else 0):
        corners = positions[triangles[piece == p]]
        low, high = corners.min(axis=(0, 1)), corners.max(axis=(0, 1))
        ask = np.flatnonzero(np.all((points >= low) & (points <= high), axis=1))
        if len(ask):
            out[ask] = np.maximum(out[ask], winding_numbers(corners, points[ask]))
    return out


def _frame(normal):
    """Two unit vectors (3,) completing the unit ``normal`` (3,) to an orthonormal frame."""
    tangent = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    tangent /= np.linalg.norm(tangent)
    return tangent, np.cross(normal, tangent)


def _enclosed(tree, origin, normal):
    """Whether rays from ``origin`` along ``normal`` and six directions 60° off it all first meet a back face."""
    tangent, bitangent = _frame(normal)
    angle = np.arange(6) * np.pi / 3 + 0.1                           # off the axes, so no ray runs along a wall
    directions = np.vstack([normal, 0.5 * normal + np.sqrt(0.75) * (np.outer(np.cos(angle), tangent)
                                                                    + np.outer(np.sin(angle), bitangent))])
    start = Vector(origin.tolist())
    for d in directions.tolist():
        hit, face_normal, _, _ = tree.ray_cast(start, Vector(d))
        if hit is None or face_normal.dot(Vector(d)) <= 0.0:
            return False
    return True


def reference_at_visible_points(mesh, count=500, rays=4096, seed=3):
    """The plain reference at ``count`` visible points of a mesh, with the maximum distance used.

    ``mesh`` has ``positions``, ``triangles``, ``corner_normals`` (t, 3, 3) and
    ``triangle_normal`` (t, 3) (a :class:`seamless_ao.core.mesh.triangle_mesh.TriangleMesh`);
    the maximum distance is half the bounding-box diagonal.

    Returns triangle (k,), bary (k, 3), shading normals (k, 3), AO (k,), max_distance.
    """
    max_distance = 0.5 * float(np.linalg.norm(mesh.positions.max(axis=0) - mesh.positions.min(axis=0)))
    triangle, bary, points = visible_points(mesh.positions, mesh.triangles, count, seed=seed)
    normals = np.einsum("kc,kcd->kd", bary, mesh.corner_normals[triangle])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    reference = plain_ao(mesh.positions, mesh.triangles, points, normals, mesh.triangle_normal[triangle],
                         max_distance, rays=rays, seed=seed + 1)
    return triangle, bary, normals, reference, max_distance


def locate(positions, triangles, points):
    """The triangle (k,) and barycentrics (k, 3) of surface points (k, 3) (nearest triangle)."""
    positions = np.asarray(positions, dtype=np.float64)
    tree = BVHTree.FromPolygons(positions.tolist(), np.asarray(triangles).tolist(), all_triangles=True)
    found = np.array([tree.find_nearest(Vector(p))[2] for p in np.asarray(points).tolist()])
    a, b, c = (positions[triangles[found, k]] for k in range(3))
    edges = np.stack([b - a, c - a], axis=2)                                     # (k, 3, 2)
    uv = np.stack([np.linalg.lstsq(e, d, rcond=None)[0] for e, d in zip(edges, points - a)])
    return found, np.stack([1.0 - uv.sum(axis=1), uv[:, 0], uv[:, 1]], axis=1)
