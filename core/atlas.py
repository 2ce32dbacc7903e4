"""Charts to one packed atlas (thesis §7.6, with xatlas instead of its naive packer).

Every chart is its faces projected on the chart's axis plane (drop one
coordinate, :data:`.clustering.BASES` keeps the image unmirrored), scaled by
one texel density for all charts.  xatlas places the charts (no rotation, so
side charts keep +Z up); the placement of each chart is then read back as an
affine map from chart-plane coordinates to texels, and every UV is computed
from it in float64.  Texel coordinates: texel ``(x, y)`` covers
``[x, x+1] x [y, y+1]``, its centre is ``(x + 0.5, y + 0.5)``, row 0 is the
bottom row (Blender's image and UV convention); UV = texel / size.
"""

from dataclasses import dataclass, field, replace

import numpy as np

from .clustering import project
from .errors import SeamlessAOError
from .mesh import cross2d

#: Tolerated mismatch between xatlas' output and its fitted affine map, in texels.
AFFINE_TOLERANCE = 1e-2


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
    membership : (t, 3) int64
        Member of each triangle on axis X, Y, Z (``-1``: not in a chart there).
    dominant_member : (t,) int64
        Member of each triangle on its face's dominant axis (never ``-1``).
    member_placed : (m,) bool
        False for members added for faces in no chart (zero area, or too thin
        for xatlas to place): they borrow a neighbour's chart and own no texels.
    charts : Charts
        The charts as packed (faces xatlas could not place are taken out).
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

    @property
    def size(self):
        return np.array([self.width, self.height], dtype=np.float64)

    def layer_uv(self):
        """(t, 3, 3, 2) float64: UV of each triangle corner in layers ``AO_X``, ``AO_Y``, ``AO_Z``.

        A triangle with no chart on an axis repeats its dominant chart there
        (thesis §7.1.1), so all three lookups read the same surface.
        """
        member = np.where(self.membership >= 0, self.membership, self.dominant_member[:, None])
        uv = self.member_uv[member] / self.size
        return np.clip(uv, 0.5 / self.size, 1.0 - 0.5 / self.size)


def chart_members(mesh, charts):
    """Every (triangle, chart) pair, degenerate triangles included.

    Returns
    -------
    member_triangle, member_chart : (m,) int64
    membership : (t, 3) int64
        Member index of each triangle per axis, ``-1`` where it has no chart.
    """
    per_axis = charts.chart_of_face[mesh.triangle_face]             # (t, 3)
    triangle, axis = np.nonzero(per_axis >= 0)
    membership = np.full(per_axis.shape, -1, dtype=np.int64)
    membership[triangle, axis] = np.arange(len(triangle))
    return triangle.astype(np.int64), per_axis[triangle, axis], membership


def chart_plane_area(mesh, charts):
    """Total area of all charts in their planes (object units squared)."""
    member_triangle, member_chart, _ = chart_members(mesh, charts)
    uv, _ = project(mesh.positions[mesh.triangles[member_triangle]], charts.chart_axis[member_chart][:, None])
    return float(0.5 * np.abs(cross2d(uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0])).sum())


def estimate_density(area, image_size, utilisation=0.55):
    """Texels per object unit that would fill ``utilisation`` of a square image."""
    return float(np.sqrt(utilisation * image_size**2 / max(area, 1e-300)))


def pack_charts(mesh, topology, charts, padding=4, image_size=None, density=None, max_size=16384):
    """Pack all charts into one image.

    Parameters
    ----------
    mesh : TriangleMesh
    topology : Topology
    charts : Charts
    padding : int
        Texels between charts (xatlas padding; at least 2 so bilinear
        filtering at a chart border never reads another chart).
    image_size : int, optional
        Square image size; the density is the largest that fits (found with
        a few xatlas runs).
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
    import xatlas  # bundled wheel; imported here so the rest of core works without it

    if (image_size is None) == (density is None):
        raise ValueError("give exactly one of image_size and density")
    member_triangle, member_chart, membership = chart_members(mesh, charts)
    local_uv, _ = project(mesh.positions[mesh.triangles[member_triangle]], charts.chart_axis[member_chart][:, None])
    live = ~mesh.degenerate[member_triangle]
    if not live.any():
        raise SeamlessAOError("The mesh has no face with area; there is nothing to pack")

    live_members = np.flatnonzero(live)
    chart_low, chart_high = _chart_boxes(local_uv[live_members], member_chart[live_members], charts.count)

    def run(resolution, texels_per_unit):
        faces = _xatlas_faces(local_uv, member_chart, topology.welded_triangles[member_triangle], live_members,
                              chart_low, chart_high, texels_per_unit)
        atlas = xatlas.Atlas()
        # Texel units from each chart's own corner: xatlas works in float32 and
        # drops faces it finds degenerate (an object 1e5 units from the origin
        # would otherwise lose whole texels).
        vertex_chart = np.zeros(len(faces.vertex_uv), dtype=np.int64)
        vertex_chart[faces.indices.astype(np.int64).ravel()] = np.repeat(faces.chart, 3)
        local = (faces.vertex_uv - chart_low[vertex_chart]) * texels_per_unit
        atlas.add_uv_mesh(local.astype(np.float32), faces.indices, faces.materials)
        options = xatlas.PackOptions()
        options.padding = int(padding)
        options.bilinear = True
        options.rotate_charts = False
        options.rotate_charts_to_axis = False
        options.resolution = int(resolution)
        options.texels_per_unit = 1.0
        atlas.generate(xatlas.ChartOptions(), options)
        return atlas, faces

    if image_size is not None:
        area = chart_plane_area(mesh, charts)
        guess = estimate_density(area, image_size, 0.7)
        probe, _ = run(0, guess)                      # one atlas of whatever size this density needs
        trial = guess * image_size / max(probe.width, probe.height) * 0.98
        for _ in range(12):
            packed, faces = run(image_size, trial)
            if packed.atlas_count == 1:
                break
            trial *= 0.95
        else:
            raise SeamlessAOError(
                "xatlas could not pack the charts into a {0}x{0} image; try a larger image size".format(image_size))
        width = height = int(image_size)
    else:
        # xatlas has no memory limit of its own: refuse what cannot fit before asking it.
        needed = max(np.sqrt(chart_plane_area(mesh, charts)) * density,
                     float((chart_high - chart_low).max()) * density + 2 * padding)
        if needed > max_size:
            raise SeamlessAOError(
                "A texel density of {:g} needs an image of about {:.0f} texels or more across, larger than {}; "
                "lower the density".format(density, needed, max_size))
        packed, faces = run(0, density)
        width, height = (int(-(-packed.width // 4) * 4), int(-(-packed.height // 4) * 4))
        if max(width, height) > max_size:
            raise SeamlessAOError(
                "A texel density of {:g} needs a {}x{} image, larger than {}; lower the density".format(
                    density, width, height, max_size))
    if packed.atlas_count != 1:
        raise SeamlessAOError("xatlas split the charts over {} images; expected one".format(packed.atlas_count))

    _, out_indices, out_uv = packed[0]
    packed_uv = out_uv.astype(np.float64)[out_indices.astype(np.int64)] * [packed.width, packed.height]
    transforms, transform_of_member = _fit_chart_transforms(packed, faces, packed_uv, member_chart)
    transform_of_member = _borrow_transforms(mesh, charts, member_triangle, member_chart, transform_of_member)
    if (transform_of_member < 0).any():
        raise SeamlessAOError("xatlas left {} chart(s) unplaced; please report this mesh".format(
            len(np.unique(member_chart[transform_of_member < 0]))))
    member_uv = _apply(transforms[transform_of_member], local_uv)

    # Triangles of faces in no chart (zero area, or too thin for xatlas) get
    # a member in a neighbour's chart.
    orphan_triangle, orphan_chart = _adopt_orphans(mesh, topology, charts)
    if len(orphan_triangle):
        orphan_transform = transform_of_member[_first_member_of_chart(member_chart, orphan_chart)]
        orphan_local, _ = project(mesh.positions[mesh.triangles[orphan_triangle]], charts.chart_axis[orphan_chart][:, None])
        member_uv = np.concatenate([member_uv, _apply(transforms[orphan_transform], orphan_local)])
        member_triangle = np.concatenate([member_triangle, orphan_triangle])
        member_chart = np.concatenate([member_chart, orphan_chart])
    dominant_member = np.full(len(mesh.triangles), -1, dtype=np.int64)
    face_dominant = charts.dominant_axis[mesh.triangle_face]
    live_face = face_dominant >= 0
    dominant_member[live_face] = membership[live_face, face_dominant[live_face] // 2]
    dominant_member[orphan_triangle] = len(member_triangle) - len(orphan_triangle) + np.arange(len(orphan_triangle))
    # Area-weighted: xatlas enlarges charts thinner than a texel, which says
    # nothing about the density of the rest.
    texel_area = np.abs(np.linalg.det(transforms[transform_of_member, :, :2]))
    local_area = 0.5 * np.abs(cross2d(local_uv[:, 1] - local_uv[:, 0], local_uv[:, 2] - local_uv[:, 0]))
    packed_density = float(np.sqrt((texel_area * local_area).sum() / max(local_area.sum(), 1e-300)))
    return Atlas(
        width=width, height=height, density=packed_density,
        utilisation=float(packed.get_utilization(0)) * packed.width * packed.height / (width * height),
        member_triangle=member_triangle, member_chart=member_chart, member_uv=member_uv,
        membership=membership, dominant_member=dominant_member,
        member_placed=np.arange(len(member_triangle)) < len(member_triangle) - len(orphan_triangle),
        charts=charts)


def _apply(transform, points):
    """Affine ``transform`` (..., 2, 3) applied to ``points`` (..., k, 2)."""
    return np.einsum("...ij,...kj->...ki", transform[..., :2], points) + transform[..., None, :, 2]


@dataclass
class _XatlasFaces:
    """What xatlas is given: real chart triangles, and box proxies for thin charts."""

    vertex_uv: np.ndarray      # (v, 2) chart-plane coordinates
    indices: np.ndarray        # (f, 3) uint32
    materials: np.ndarray      # (f, 1) uint32: chart of each face
    source_uv: np.ndarray      # (f, 3, 2) chart-plane corners of each face
    member: np.ndarray         # (f,) member of each face, -1 for proxies
    chart: np.ndarray          # (f,) chart of each face


def _chart_boxes(local_uv, member_chart, chart_count):
    """Bounding box (low, high), each (c, 2), of every chart in its plane."""
    low = np.full((chart_count, 2), np.inf)
    high = np.full((chart_count, 2), -np.inf)
    np.minimum.at(low, member_chart, local_uv.min(axis=1))
    np.maximum.at(high, member_chart, local_uv.max(axis=1))
    return low, high


def _xatlas_faces(local_uv, member_chart, member_welded, live_members, chart_low, chart_high, density):
    """xatlas input at ``density``.

    A chart thinner than two texels is given as its bounding box widened to
    two texels (two triangles) instead of its triangles: xatlas reserves the
    space and the placement of the box places the chart, where the real sliver
    might be dropped as degenerate.  Other charts go in as their triangles,
    one vertex per (chart, welded vertex) so each stays one xatlas chart.
    """
    thin = ((chart_high - chart_low) * density < 2.0).any(axis=1)
    real = live_members[~thin[member_chart[live_members]]]
    welded = member_welded[real]
    key = member_chart[real, None] * np.int64(welded.max() + 1 if len(welded) else 1) + welded
    vertex_key, vertex_index = np.unique(key.ravel(), return_inverse=True)
    vertex_uv = np.zeros((len(vertex_key), 2))
    vertex_uv[vertex_index.reshape(-1)] = local_uv[real].reshape(-1, 2)
    indices = vertex_index.reshape(-1, 3)
    thin_charts = np.flatnonzero(thin & np.isfinite(chart_low[:, 0]))
    centre = 0.5 * (chart_low[thin_charts] + chart_high[thin_charts])
    half = np.maximum(0.5 * (chart_high[thin_charts] - chart_low[thin_charts]), 1.0 / density)
    corners = np.stack([centre - half, centre + [1, -1] * half, centre + half, centre + [-1, 1] * half], axis=1)
    first = len(vertex_uv) + 4 * np.arange(len(thin_charts))
    proxy_indices = np.concatenate([np.stack([first, first + 1, first + 2], 1), np.stack([first, first + 2, first + 3], 1)])
    proxy_chart = np.concatenate([thin_charts, thin_charts])
    all_uv = np.concatenate([vertex_uv, corners.reshape(-1, 2)])
    all_indices = np.concatenate([indices, proxy_indices]).astype(np.int64)
    chart = np.concatenate([member_chart[real], proxy_chart])
    return _XatlasFaces(
        vertex_uv=all_uv, indices=all_indices.astype(np.uint32), materials=chart[:, None].astype(np.uint32),
        source_uv=all_uv[all_indices], member=np.concatenate([real, np.full(len(proxy_chart), -1)]), chart=chart)


def _fit_chart_transforms(packed, faces, packed_uv, member_chart):
    """Least-squares affine map, chart plane -> texels, of every xatlas chart.

    Returns ``transforms`` (k, 2, 3) and the transform of each member (``-1``
    for members no placed face speaks for: degenerate triangles).
    """
    transform_of_member = np.full(len(member_chart), -1, dtype=np.int64)
    transforms = []
    for index in range(packed.get_mesh_chart_count(0)):
        chart_faces = np.asarray(packed.get_mesh_chart(0, index).faces, dtype=np.int64)
        source = faces.source_uv[chart_faces].reshape(-1, 2)
        target = packed_uv[chart_faces].reshape(-1, 2)
        centre = source.mean(axis=0)
        design = np.column_stack([source - centre, np.ones(len(source))])
        solution, *_ = np.linalg.lstsq(design, target, rcond=None)
        residual = np.abs(design @ solution - target).max()
        if residual > AFFINE_TOLERANCE + 1e-6 * np.abs(target).max():
            raise SeamlessAOError("xatlas reshaped a chart (off by {:.3g} texels); please report this mesh".format(
                residual))
        linear = solution[:2].T
        if np.linalg.det(linear) <= 0:
            raise SeamlessAOError("xatlas mirrored a chart; please report this mesh")
        offset = solution[2] - linear @ centre
        transforms.append(np.column_stack([linear, offset]))
        members = faces.member[chart_faces]
        transform_of_member[members[members >= 0]] = index
        proxied = np.unique(faces.chart[chart_faces[members < 0]])
        if len(proxied):
            transform_of_member[np.isin(member_chart, proxied)] = index
    return np.array(transforms, dtype=np.float64).reshape(-1, 2, 3), transform_of_member


def _borrow_transforms(mesh, charts, member_triangle, member_chart, transform_of_member):
    """Members xatlas did not place (degenerate or sub-texel triangles) take a placed one's transform.

    First choice: a placed member of the same face and chart; else any placed
    member of the same chart.  Members of charts xatlas placed nothing of keep
    ``-1`` (they are too small to matter; see :func:`pack_charts`).
    """
    missing = transform_of_member < 0
    if not missing.any():
        return transform_of_member
    transform_of_member = transform_of_member.copy()
    placed = np.flatnonzero(~missing)
    for key in (mesh.triangle_face[member_triangle] * np.int64(charts.count + 1) + member_chart, member_chart):
        want = np.flatnonzero(transform_of_member < 0)
        if not len(want) or not len(placed):
            break
        placed_key, first = np.unique(key[placed], return_index=True)
        position = np.minimum(np.searchsorted(placed_key, key[want]), len(placed_key) - 1)
        found = placed_key[position] == key[want]
        transform_of_member[want[found]] = transform_of_member[placed[first[position[found]]]]
    return transform_of_member


def _first_member_of_chart(member_chart, charts_wanted):
    """Index of the first member of each chart in ``charts_wanted``."""
    order = np.argsort(member_chart, kind="stable")
    return order[np.searchsorted(member_chart[order], charts_wanted)]


def _adopt_orphans(mesh, topology, charts):
    """A chart for every triangle of a face in no chart: a charted neighbour's dominant chart.

    Returns ``(triangles, charts)`` as (k,) int64 arrays; a face with no
    charted neighbour takes chart 0 (it is too small to show anything).
    """
    dead_face = (charts.chart_of_face < 0).all(axis=1)
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
