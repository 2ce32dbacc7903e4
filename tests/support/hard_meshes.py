"""Generated hard meshes for issue 7: each returns (positions (v, 3), faces as lists of vertex indices)."""

import numpy as np

import meshes


def as_faces(triangles):
    return [list(map(int, t)) for t in triangles]


def scaled_suzanne_like(scale):
    """A bumpy closed sphere with a dent, scaled (for scale invariance)."""
    positions, triangles = meshes.uv_sphere(rings=20, segments=40)
    bump = 1.0 + 0.25 * np.exp(-((positions[:, 0] - 0.7) ** 2 + positions[:, 1] ** 2) * 8.0)
    dent = 1.0 - 0.35 * np.exp(-((positions[:, 2] - 0.9) ** 2) * 10.0)
    return positions * (bump * dent)[:, None] * scale, as_faces(triangles)


def far_from_origin(offset=1e5):
    positions, faces = scaled_suzanne_like(1.0)
    return positions + [offset, -offset, 0.5 * offset], faces


def slivers():
    """A plate whose top is a fan of slivers (aspect ratio ~1e6), plus zero-area triangles."""
    n = 600
    angles = np.linspace(0.0, np.pi * 1e-3, n)         # a very thin fan
    rim = np.stack([np.cos(angles), np.sin(angles), np.zeros(n)], 1)
    positions = np.vstack([[[0.0, 0.0, 0.0]], rim, [[0.5, -0.5, 0.0], [0.5, -0.2, 0.0], [0.6, -0.3, 0.0]]])
    faces = [[0, i, i + 1] for i in range(1, n)]
    faces += [[n + 1, n + 2, n + 3]]                    # an ordinary triangle beside it
    faces += [[n + 1, n + 1, n + 2]]                    # repeated vertex: zero area
    collinear = len(positions)
    positions = np.vstack([positions, [[0.2, -0.6, 0.0], [0.3, -0.6, 0.0], [0.4, -0.6, 0.0]]])
    faces += [[collinear, collinear + 1, collinear + 2]]   # collinear: zero area
    # a wall along the fan's thin side, facing it, so the slivers' AO is not 1 everywhere
    wall = len(positions)
    positions = np.vstack([positions, [[0.0, 0.02, 0.0], [1.0, 0.02, 0.0], [1.0, 0.02, 0.3], [0.0, 0.02, 0.3]]])
    faces += [[wall, wall + 1, wall + 2, wall + 3]]
    return positions, faces


def coplanar_duplicates():
    """A box with some faces twice, standing on a floor (so its sides darken toward the floor)."""
    positions, triangles = meshes.box(subdivisions=2)
    faces = as_faces(triangles) + as_faces(triangles[:8])      # some faces twice
    return _with_floor(positions, faces, height=-0.5)


def two_walls(gap=1e-4):
    """Two thin parallel plates gap apart (front faces toward each other)."""
    a, ta = meshes.box(size=(1.0, 1.0, 0.02), center=(0.0, 0.0, 0.0), subdivisions=2)
    b, tb = meshes.box(size=(1.0, 1.0, 0.02), center=(0.0, 0.0, 0.02 + gap), subdivisions=2)
    return np.vstack([a, b]), as_faces(ta) + as_faces(tb + len(a))


def open_bowl():
    """A hemisphere without its lid or back (open, single-sided), hovering over a floor."""
    positions, triangles = meshes.uv_sphere(rings=24, segments=48)
    keep = positions[triangles].mean(axis=1)[:, 2] < 0.0
    return _with_floor(positions, as_faces(triangles[keep]), height=-1.15)


def _with_floor(positions, faces, height, half=1.5):
    """``positions``, ``faces`` plus a square floor facing up at ``height``."""
    start = len(positions)
    floor = [[-half, -half, height], [half, -half, height], [half, half, height], [-half, half, height]]
    return np.vstack([positions, floor]), faces + [[start, start + 1, start + 2, start + 3]]


def fin():
    positions, triangles = meshes.box(subdivisions=2)
    top_first = 4 * 9
    top_middle = sorted([top_first + i for i in range(9)
                         if abs(positions[top_first + i][0]) < 1e-9 and abs(positions[top_first + i][2] - 0.5) < 1e-9],
                        key=lambda i: positions[i][1])
    a, mid, b = top_middle
    c, d = len(positions), len(positions) + 1
    positions = np.vstack([positions, [[0.0, positions[a][1], 1.0], [0.0, positions[b][1], 1.0]]])
    return positions, as_faces(triangles) + [[a, mid, c], [mid, b, d], [mid, d, c]]


def ngons():
    """A prism whose caps are concave 10-pointed stars (n-gons) and whose sides are quads."""
    k = 10
    angles = np.linspace(0, 2 * np.pi, 2 * k, endpoint=False)
    radius = np.where(np.arange(2 * k) % 2 == 0, 1.0, 0.45)
    ring = np.stack([radius * np.cos(angles), radius * np.sin(angles)], 1)
    bottom = np.column_stack([ring, np.zeros(2 * k)])
    top = np.column_stack([ring, np.full(2 * k, 0.4)])
    positions = np.vstack([bottom, top])
    n = 2 * k
    faces = [list(range(n))[::-1], list(range(n, 2 * n))]
    faces += [[i, (i + 1) % n, n + (i + 1) % n, n + i] for i in range(n)]
    return positions, faces


def flipped_normals():
    positions, faces = scaled_suzanne_like(1.0)
    return positions, [f[::-1] for f in faces]


def diagonal_normals():
    """An octahedron (normals on the (1,1,1) diagonals, 54.7 degrees) on a 45-degree roof."""
    octa = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float) + [0, 0, 2.0]
    faces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    roof = np.array([[-1.5, -1.5, 0.0], [1.5, -1.5, 0.0], [1.5, 1.5, 0.0], [-1.5, 1.5, 0.0],
                     [-1.5, 0.0, 1.5], [1.5, 0.0, 1.5]])
    r = len(octa)
    faces += [[r + 0, r + 1, r + 5, r + 4], [r + 4, r + 5, r + 2, r + 3]]     # normals (0, -1, 1)/sqrt2 and (0, 1, 1)/sqrt2
    return np.vstack([octa, roof]), faces


def spike(far=1e3):
    """The bumpy sphere (1,520 triangles) with one thin triangle, a thousandth of a unit wide at its base,
    reaching a stray vertex ``far`` out (a scan's outlier): the rest must bake as if it were not there."""
    positions, faces = scaled_suzanne_like(1.0)
    first = faces[0][0]
    positions = np.vstack([positions, positions[first] + [0.0, 0.0, 1e-3], [[far, 0.0, 0.0]]])
    return positions, faces + [[first, len(positions) - 2, len(positions) - 1]]


def single_triangle():
    return np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.3]]), [[0, 1, 2]]


HARD_MESHES = {
    "tiny": lambda: scaled_suzanne_like(1e-3),
    "huge": lambda: scaled_suzanne_like(1e4),
    "far": far_from_origin,
    "slivers": slivers,
    "duplicates": coplanar_duplicates,
    "two-walls": two_walls,
    "open": open_bowl,
    "fin": fin,
    "ngons": ngons,
    "flipped": flipped_normals,
    "diagonals": diagonal_normals,
    "single-triangle": single_triangle,
}
