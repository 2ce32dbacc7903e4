"""Generated stand-ins for the assets users bake (numpy only, no downloaded files).

Each function returns ``positions (v, 3) float64, triangles (t, 3) int64``:

- :func:`interior`: a hall of well over 1,000 separate pieces and 60k+
  triangles (floor, walls, columns, arches, thin railings, crates standing on
  the floor, wavy drapes), the kind of scene whose many small charts made
  packing fail;
- :func:`noisy_scan`: one connected closed surface of about 100k triangles
  with scanner-like noise and a few holes;
- :func:`chips`: 10,000 tiny disconnected chips;
- :func:`long_thin`: a beam with aspect 1:1000.

Every generator is deterministic (fixed seeds).
"""

import numpy as np

from meshes import _orient_each, box, grid_triangles


class _Builder:
    """Collects separate pieces into one vertex and triangle list."""

    def __init__(self):
        self.positions, self.triangles, self.count = [], [], 0
        self.pieces = 0

    def add(self, positions, triangles):
        self.triangles.append(np.asarray(triangles, dtype=np.int64) + self.count)
        self.positions.append(np.asarray(positions, dtype=np.float64))
        self.count += len(positions)
        self.pieces += 1

    def mesh(self):
        return np.vstack(self.positions), np.vstack(self.triangles)


def cylinder(radius, height, segments, rings, center=(0.0, 0.0, 0.0)):
    """Closed cylinder along +Z standing on ``center`` (outward normals)."""
    angle = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    z = np.linspace(0.0, height, rings + 1)
    a, h = np.meshgrid(angle, z, indexing="ij")
    side = np.stack([radius * np.cos(a), radius * np.sin(a), h], -1).transpose(1, 0, 2).reshape(-1, 3)
    tris = grid_triangles(rings + 1, segments, wrap_cols=True)
    bottom, top = len(side), len(side) + 1
    k = np.arange(segments)
    caps = np.concatenate([np.stack([np.full(segments, bottom), (k + 1) % segments, k], -1),
                           np.stack([np.full(segments, top), rings * segments + k,
                                     rings * segments + (k + 1) % segments], -1)])
    positions = np.vstack([side, [[0, 0, 0], [0, 0, height]]]) + np.asarray(center)
    return positions, np.vstack([tris, caps])


def arch(span, rise, thickness, depth, steps, center=(0.0, 0.0, 0.0), along_y=False):
    """A closed semicircular arch (a bent box) spanning ``span`` in X (or Y), top at ``rise``."""
    angle = np.linspace(0.0, np.pi, steps + 1)
    radius = 0.5 * span
    out = []
    for r in (radius + 0.5 * thickness, radius - 0.5 * thickness):
        for d in (-0.5 * depth, 0.5 * depth):
            out.append(np.stack([r * np.cos(angle), np.full_like(angle, d), rise - radius + r * np.sin(angle)], -1))
    ring = np.stack(out, axis=1)                                  # (steps+1, 4, 3): outer-, outer+, inner-, inner+
    positions = ring.reshape(-1, 3)
    i = np.arange(steps)[:, None] * 4
    quads = []
    for a, b in ((0, 1), (1, 3), (3, 2), (2, 0)):                 # outer, front, inner, back faces
        quads.append(np.concatenate([i + a, i + 4 + a, i + 4 + b, i + b], axis=1))
    quads = np.vstack(quads)
    ends = np.array([[0, 2, 3, 1], [4 * steps + 0, 4 * steps + 1, 4 * steps + 3, 4 * steps + 2]])
    quads = np.vstack([quads, ends])
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    # outward: away from the nearest point of the arch's centre line (kept off the ends,
    # so the end caps face along the line)
    centre = positions[tris].mean(axis=1)
    angle = np.clip(np.arctan2(centre[:, 2] - (rise - radius), centre[:, 0]), 0.01, np.pi - 0.01)
    core = np.stack([radius * np.cos(angle), np.zeros_like(angle), rise - radius + radius * np.sin(angle)], -1)
    tris = _orient_each(positions, tris, centre - core)
    if along_y:
        positions = positions[:, [1, 0, 2]]
        tris = tris[:, ::-1]
    return positions + np.asarray(center), tris


def drape(width, height, folds, rows, cols, center=(0.0, 0.0, 0.0)):
    """An open wavy curtain hanging in the XZ plane (one-sided sheet, facing -Y)."""
    u = np.linspace(-0.5, 0.5, cols) * width
    v = np.linspace(0.0, 1.0, rows) * height
    U, V = np.meshgrid(u, v, indexing="ij")
    Y = 0.04 * width * np.sin(2 * np.pi * folds * U / width) * (0.6 + 0.4 * V / height)
    positions = np.stack([U, Y, V], -1).transpose(1, 0, 2).reshape(-1, 3)
    return positions + np.asarray(center), grid_triangles(rows, cols)


def interior(seed=0):
    """A colonnaded hall of about 1,300 separate parts (1,157 pieces once touching parts count as one), 94,412
    triangles (tests/bench/bench_meshes.py counts them; see module doc)."""
    rng = np.random.default_rng(seed)
    scene = _Builder()
    scene.add(*box(size=(40.0, 24.0, 0.2), center=(0, 0, -0.1), subdivisions=8))          # floor
    for x in (-20.0, 20.0):
        scene.add(*box(size=(0.3, 24.0, 10.0), center=(x, 0, 5.0), subdivisions=6))
    for y in (-12.0, 12.0):
        scene.add(*box(size=(40.0, 0.3, 10.0), center=(0, y, 5.0), subdivisions=6))
    # two colonnades of columns with a base and a capital, arches between them
    xs = np.linspace(-18.0, 18.0, 13)
    for y in (-6.0, 6.0):
        for x in xs:
            scene.add(*box(size=(0.9, 0.9, 0.3), center=(x, y, 0.15)))
            scene.add(*cylinder(0.3, 6.0, 32, 24, center=(x, y, 0.3)))
            scene.add(*box(size=(0.9, 0.9, 0.3), center=(x, y, 6.45)))
        for a, b in zip(xs[:-1], xs[1:]):
            scene.add(*arch(b - a, 2.0, 0.4, 0.6, 24, center=(0.5 * (a + b), y, 6.6)))
    # thin railings along the side aisles: posts and a rail per bay
    for y in (-9.0, 9.0):
        for x in np.linspace(-19.0, 19.0, 77):
            scene.add(*box(size=(0.04, 0.04, 1.0), center=(x, y, 0.5)))
        for a, b in zip(np.linspace(-19.0, 19.0, 77)[:-1], np.linspace(-19.0, 19.0, 77)[1:]):
            scene.add(*box(size=(b - a - 0.04, 0.03, 0.03), center=(0.5 * (a + b), y, 1.0)))
            scene.add(*box(size=(b - a - 0.04, 0.02, 0.02), center=(0.5 * (a + b), y, 0.5)))
    # crates and benches standing on the floor
    for _ in range(600):
        size = rng.uniform(0.2, 1.2, 3)
        x, y = rng.uniform(-19.0, 19.0), rng.uniform(-11.0, 11.0)
        scene.add(*box(size=size, center=(x, y, 0.5 * size[2])))
    # drapes on the walls
    for x in np.linspace(-17.0, 17.0, 9):
        for y, flip in ((-11.7, True), (11.7, False)):                  # facing into the hall
            positions, tris = drape(3.0, 7.0, 5, 24, 40, center=(x, y, 1.5))
            scene.add(positions, tris[:, ::-1] if flip else tris)
    return scene.mesh()


def noisy_scan(triangles=100_000, holes=4, seed=0, noise=0.002):
    """One connected closed-then-holed surface: a lumpy, noisy sphere (about ``triangles`` triangles), its
    scanner ``noise`` the standard deviation of each vertex's radius (object units; the sphere's radius is 1)."""
    rng = np.random.default_rng(seed)
    segments = int(np.sqrt(triangles))
    rings = max(4, triangles // (2 * segments) + 1)
    theta = np.linspace(0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    direction = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    radius = 1.0 + 0.15 * np.sin(3 * t) * np.cos(2 * p) + 0.05 * np.sin(11 * t + 1.0) * np.sin(13 * p)
    radius = radius + rng.normal(0.0, noise, radius.shape)                                # scanner noise
    body = (direction * radius[..., None]).reshape(-1, 3)
    positions = np.vstack([body, [[0, 0, 1.0], [0, 0, -1.0]]])
    r, c = np.meshgrid(np.arange(len(theta) - 1), np.arange(segments), indexing="ij")
    a, b = r * segments + c, r * segments + (c + 1) % segments
    d, e = a + segments, b + segments
    quads = np.concatenate([np.stack([a, e, b], -1).reshape(-1, 3), np.stack([a, d, e], -1).reshape(-1, 3)])
    k = np.arange(segments)
    top, bottom, last = len(body), len(body) + 1, (len(theta) - 1) * segments
    caps = np.concatenate([np.stack([np.full(segments, top), (k + 1) % segments, k], -1),
                           np.stack([np.full(segments, bottom), last + k, last + (k + 1) % segments], -1)])
    tris = np.vstack([quads, caps])
    centre = positions[tris].mean(axis=1)
    centre /= np.linalg.norm(centre, axis=1, keepdims=True)
    keep = np.ones(len(tris), dtype=bool)
    for hole in rng.normal(size=(holes, 3)):
        hole /= np.linalg.norm(hole)
        keep &= centre @ hole < np.cos(np.radians(rng.uniform(4.0, 9.0)))
    return positions, tris[keep]


def chips(count=10_000, size=1e-3, extent=1.0, seed=0):
    """``count`` tiny closed tetrahedra scattered in a cube of side ``extent``."""
    rng = np.random.default_rng(seed)
    base = np.array([[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]])
    faces = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    # random rotations (QR of a Gaussian matrix), sizes and places
    q, r = np.linalg.qr(rng.normal(size=(count, 3, 3)))
    q *= np.sign(np.linalg.det(q))[:, None, None]
    scale = size * rng.uniform(0.5, 2.0, count)
    corners = np.einsum("kij,vj->kvi", q, base) * scale[:, None, None] + rng.uniform(
        -0.5 * extent, 0.5 * extent, (count, 1, 3))
    tris = faces[None] + 4 * np.arange(count)[:, None, None]
    positions, tris = corners.reshape(-1, 3), tris.reshape(-1, 3)
    return positions, _orient_outward_pieces(positions, tris, 4)


def beam(length, width, height, segments, center=(0.0, 0.0, 0.0)):
    """A closed box beam along X, cut into ``segments`` along its length (outward normals)."""
    x = np.linspace(-0.5, 0.5, segments + 1) * length
    section = np.array([[-width, -height], [width, -height], [width, height], [-width, height]]) * 0.5
    positions = np.concatenate([np.column_stack([np.full(4, xi), section]) for xi in x])
    i = np.arange(segments)[:, None] * 4
    quads = np.vstack([np.concatenate([i + k, i + 4 + k, i + 4 + (k + 1) % 4, i + (k + 1) % 4], axis=1)
                       for k in range(4)])
    last = 4 * segments
    quads = np.vstack([quads, [[0, 3, 2, 1], [last, last + 1, last + 2, last + 3]]])
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    centre = positions[tris].mean(axis=1)
    end = np.abs(centre[:, :1]) >= 0.5 * length - 1e-9
    outward = np.where(end, np.sign(centre[:, :1]) * [[1.0, 0.0, 0.0]], centre * [0.0, 1.0, 1.0])
    return positions + np.asarray(center), _orient_each(positions, tris, outward)


def long_thin(length=1000.0, width=1.0, segments=1000):
    """A beam ``length`` long with a square section of side ``width`` (aspect 1:1000), with a
    narrower ledge standing on it that shadows its top."""
    scene = _Builder()
    scene.add(*beam(length, width, width, segments))
    scene.add(*beam(length, 0.2 * width, 0.5 * width, segments, center=(0.0, 0.0, 0.75 * width)))
    return scene.mesh()


def _orient_outward_pieces(positions, tris, vertices_per_piece):
    """Wind each triangle away from the centre of its piece (``vertices_per_piece`` consecutive vertices)."""
    piece_centre = positions.reshape(-1, vertices_per_piece, 3).mean(axis=1)
    outward = positions[tris].mean(axis=1) - piece_centre[tris[:, 0] // vertices_per_piece]
    return _orient_each(positions, tris, outward)


ASSETS = {
    "interior": interior,
    "noisy_scan": noisy_scan,
    "chips": chips,
    "long_thin": long_thin,
}
