"""Generated test meshes (numpy only): positions (v, 3) and triangles (t, 3)."""

import numpy as np


def grid_triangles(rows, cols, wrap_cols=False):
    """Triangles of a rows x cols vertex grid (vertex r * cols + c)."""
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(cols if wrap_cols else cols - 1), indexing="ij")
    a = r * cols + c
    b = r * cols + (c + 1) % cols
    d = (r + 1) * cols + c
    e = (r + 1) * cols + (c + 1) % cols
    return np.concatenate([np.stack([a, b, e], -1).reshape(-1, 3), np.stack([a, e, d], -1).reshape(-1, 3)])


def uv_sphere(radius=1.0, rings=24, segments=48):
    """Closed UV sphere, outward normals."""
    theta = np.linspace(0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    body = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3) * radius
    positions = np.vstack([body, [[0, 0, radius], [0, 0, -radius]]])
    tris = grid_triangles(rings - 1, segments, wrap_cols=True)
    # grid rows go from north to south: flip winding to face outward
    tris = tris[:, ::-1]
    top, bottom = len(body), len(body) + 1
    k = np.arange(segments)
    cap_top = np.stack([np.full(segments, top), k, (k + 1) % segments], -1)
    last = (rings - 2) * segments
    cap_bottom = np.stack([np.full(segments, bottom), last + (k + 1) % segments, last + k], -1)
    return positions, np.vstack([tris, cap_top, cap_bottom])


def box(size=(1.0, 1.0, 1.0), center=(0.0, 0.0, 0.0), subdivisions=1):
    """Axis-aligned box, each side an n x n grid, faces pointing outward."""
    n = subdivisions + 1
    s = np.linspace(-0.5, 0.5, n)
    u, v = np.meshgrid(s, s, indexing="ij")
    u, v = u.ravel(), v.ravel()
    tri = grid_triangles(n, n)
    positions, triangles = [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            a1, a2 = (axis + 1) % 3, (axis + 2) % 3
            p = np.zeros((len(u), 3))
            p[:, axis] = 0.5 * sign
            p[:, a1], p[:, a2] = u, v
            t = tri[:, ::-1] if sign > 0 else tri
            triangles.append(t + sum(len(x) for x in positions))
            positions.append(p)
    positions = np.vstack(positions) * np.asarray(size) + np.asarray(center)
    return positions, np.vstack(triangles)


def torus(major=1.0, minor=0.35, rings=48, segments=24):
    a = np.linspace(0, 2 * np.pi, rings, endpoint=False)
    b = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    A, B = np.meshgrid(a, b, indexing="ij")
    positions = np.stack([(major + minor * np.cos(B)) * np.cos(A), (major + minor * np.cos(B)) * np.sin(A),
                          minor * np.sin(B)], -1).reshape(-1, 3)
    r, c = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    a0 = r * segments + c
    a1 = r * segments + (c + 1) % segments
    b0 = ((r + 1) % rings) * segments + c
    b1 = ((r + 1) % rings) * segments + (c + 1) % segments
    tris = np.concatenate([np.stack([a0, b0, b1], -1).reshape(-1, 3), np.stack([a0, b1, a1], -1).reshape(-1, 3)])
    return positions, tris


def spiral_ramp(turns=3.0, inner=0.3, outer=1.0, pitch=0.25, steps_per_turn=48, width_steps=4, thickness=0.05):
    """A closed slab winding around Z: its top faces overlap in the Z projection every turn."""
    n = int(turns * steps_per_turn) + 1
    ang = np.linspace(0, 2 * np.pi * turns, n)
    rad = np.linspace(inner, outer, width_steps + 1)
    A, R = np.meshgrid(ang, rad, indexing="ij")
    top = np.stack([R * np.cos(A), R * np.sin(A), pitch * A / (2 * np.pi)], -1).reshape(-1, 3)
    bottom = top - [0, 0, thickness]
    cols = width_steps + 1
    t_top = grid_triangles(n, cols)
    # orientation: make the top face +Z
    t_top = _orient(top, t_top, np.array([0, 0, 1.0]))
    t_bot = t_top[:, ::-1] + len(top)
    positions = np.vstack([top, bottom])
    # inner and outer walls, and the two end caps
    walls = []
    m = len(top)
    for col, outward in ((0, -1.0), (width_steps, 1.0)):
        idx = np.arange(n) * cols + col
        q = np.stack([idx[:-1], idx[1:], idx[1:] + m, idx[:-1] + m], -1)
        tri = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
        centre = positions[tri].mean(1)
        radial = centre * [1, 1, 0]
        tri = _orient_each(positions, tri, radial * outward)
        walls.append(tri)
    for row, direction in ((0, -1.0), (n - 1, 1.0)):
        idx = row * cols + np.arange(cols)
        q = np.stack([idx[:-1], idx[1:], idx[1:] + m, idx[:-1] + m], -1)
        tri = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
        a = ang[row]
        tangent = np.array([-np.sin(a), np.cos(a), 0.0]) * direction
        walls.append(_orient_each(positions, tri, np.broadcast_to(tangent, (len(tri), 3))))
    return positions, np.vstack([t_top, t_bot] + walls)


def helicoid_strip(turns=2.5, radius=1.0, width=0.5, pitch=0.3, steps_per_turn=64, width_steps=6):
    """An open twisted strip whose normal swings round; it folds over itself in every projection."""
    n = int(turns * steps_per_turn) + 1
    ang = np.linspace(0, 2 * np.pi * turns, n)
    w = np.linspace(-0.5, 0.5, width_steps + 1) * width
    A, W = np.meshgrid(ang, w, indexing="ij")
    twist = A * 0.5
    positions = np.stack([
        (radius + W * np.cos(twist)) * np.cos(A),
        (radius + W * np.cos(twist)) * np.sin(A),
        pitch * A / (2 * np.pi) + W * np.sin(twist)], -1).reshape(-1, 3)
    return positions, grid_triangles(n, width_steps + 1)


def _orient(positions, tris, direction):
    c = positions[tris]
    normal = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    flip = normal @ direction < 0
    tris = tris.copy()
    tris[flip] = tris[flip][:, ::-1]
    return tris


def _orient_each(positions, tris, directions):
    c = positions[tris]
    normal = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    flip = (normal * directions).sum(1) < 0
    tris = tris.copy()
    tris[flip] = tris[flip][:, ::-1]
    return tris


def split_vertices(positions, triangles):
    """Every triangle gets its own three vertices (an STL-style import)."""
    return positions[triangles].reshape(-1, 3), np.arange(len(triangles) * 3).reshape(-1, 3)


def pierced_box():
    """A 2 x 2 x 2 box with a 0.6-wide box pushed halfway into its top, turned 30 degrees (not along any
    texel grid).

    Returns positions (v, 3), triangles (t, 3) and ``gap(points (k, 3)) -> (k,)``: each point's distance
    to the intersection, for points on the big box's top or the small box's sides (inf elsewhere).
    """
    big = box(size=(2.0, 2.0, 2.0), subdivisions=6)
    small_positions, small_triangles = box(size=(0.6, 0.6, 0.6), center=(0.0, 0.0, 1.0), subdivisions=3)
    turn = np.radians(30.0)
    rotation = np.array([[np.cos(turn), -np.sin(turn), 0], [np.sin(turn), np.cos(turn), 0], [0, 0, 1]])
    shift = np.array([0.17, -0.11, 0.0])
    positions = np.vstack([big[0], small_positions @ rotation.T + shift])
    triangles = np.vstack([big[1], small_triangles + len(big[0])])

    def gap(points):
        across = np.abs(((points - shift) @ rotation)[:, :2]).max(axis=1)   # 0.3 on the small box's sides
        on_top = np.isclose(points[:, 2], 1.0) & (across > 0.3)
        on_small = (across <= 0.3 + 1e-9) & (points[:, 2] > 1.0)
        return np.where(on_top, across - 0.3, np.where(on_small, points[:, 2] - 1.0, np.inf))

    return positions, triangles, gap
