"""Where the AO will be stored: mesh -> charts -> atlas -> texels, chained and timed (:func:`build_layout`).

Each step is also callable alone (see the modules); this module only orders
them and times them.  The whole bake, rays and image included, is :mod:`.pipeline`'s.
"""

import time
from dataclasses import dataclass, field

import numpy as np

from .atlas.chart_atlas import Atlas, expected_density, pack_charts
from .atlas.raster import Texels, rasterise
from .charts.clustering import Charts, cut_long_charts, make_injective, signed_axis_clusters
from .charts.coarse import coarse_charts, proxy_cell_texels
from .errors import SeamlessAOError
from .mesh.adjacency import face_adjacency
from .mesh.triangle_mesh import MeshReport, TriangleMesh, require_faces

#: Distant parts of one chart must stay this many texels apart (bilinear reads 1).
SEPARATION_TEXELS = 3.0
#: With a texel density given, charts longer than this many texels are cut.
LONGEST_CHART_TEXELS = 1024


@dataclass
class Layout:
    """Everything about where AO is stored, before any ray is cast.

    Several meshes (objects baked together into one shared image) are one
    combined mesh whose parts never share an edge or a chart:
    ``part_of_triangle`` says which input mesh each triangle came from.
    """

    mesh: TriangleMesh
    mesh_report: MeshReport               # what welding found (the adjacency itself is let go after packing)
    charts: Charts
    atlas: Atlas
    texels: Texels
    part_of_triangle: np.ndarray          # (t,) int: the input mesh of each triangle
    timings: dict = field(default_factory=dict)    # seconds of each step

    def part_of_texel(self, selection=slice(None)):
        """(k,) int: input mesh of each texel."""
        return self.part_of_triangle[self.atlas.member_triangle[self.texels.member[selection]]]


def build_layout(meshes, compare_angle=60.0, image_size=1024, density=None, padding=4, rays=None):
    """Charts, atlas and texels for one or several meshes (one shared image).

    Parameters
    ----------
    meshes : TriangleMesh or list of TriangleMesh
    compare_angle : float, degrees
    image_size : int or None
        Square image size (used when ``density`` is None).
    density : float or None
        Texels per object unit; overrides ``image_size``.
    padding : int, texels
    rays : int, optional, the rays per texel the bake will cast (a proxy's cubes are finer for many,
        :func:`.charts.coarse.proxy_cell_texels`)

    Returns
    -------
    Layout
    """
    meshes = [meshes] if isinstance(meshes, TriangleMesh) else list(meshes)
    for mesh in meshes:
        require_faces(mesh)
    # Several meshes are one mesh of parts from here on: parts never weld, so they never share an edge
    # or a chart, and each keeps tolerances relative to its own size.
    mesh, offsets = TriangleMesh.concatenate(meshes) if len(meshes) > 1 else (
        meshes[0], np.array([0, len(meshes[0].triangles)]))
    timings = {}
    # no chart longer than a quarter of the image at the expected density (charts are never rotated)
    longest_texels = image_size / 4 if density is None else LONGEST_CHART_TEXELS
    size = image_size if density is None else None
    cell_texels = proxy_cell_texels(mesh, compare_angle, rays, size, density) if len(meshes) == 1 else None
    if cell_texels is not None:
        # far more triangles than texels: charts made at the scale the image shows (charts/coarse.py)
        charts, topology = coarse_charts(mesh, compare_angle, size, density, SEPARATION_TEXELS, longest_texels,
                                         timings, cell_texels)
    else:
        start = time.perf_counter()
        topology = face_adjacency(mesh)
        charts = signed_axis_clusters(mesh, topology, compare_angle)
        timings["charts"] = time.perf_counter() - start

        start = time.perf_counter()
        expected = density if density is not None else expected_density(mesh, charts, image_size)
        # One injectivity pass with a margin: it splits folds (what cluster_faces
        # does) and also keeps distant parts of a chart a few texels apart, so
        # filtering at a chart's edge never mixes in AO from another surface.
        charts = make_injective(mesh, topology, charts, margin=SEPARATION_TEXELS / expected)
        charts = cut_long_charts(mesh, charts, longest_texels / expected)
        timings["injectivity"] = time.perf_counter() - start
    start = time.perf_counter()
    atlas = pack_charts(mesh, topology, charts, padding=padding,
                        image_size=None if density is not None else image_size, density=density)
    charts = atlas.charts
    timings["pack"] = time.perf_counter() - start
    mesh_report = topology.report
    del topology                          # 40 MB a million triangles, needed by no later step
    mesh.let_go_of_cross()                # and 24 MB: read by the charts and the packing only

    start = time.perf_counter()
    texels = rasterise(atlas, mesh, padding=atlas.padding)
    timings["rasterise"] = time.perf_counter() - start
    if not len(texels):
        raise SeamlessAOError("No texel landed on the mesh; raise the image size or texel density")
    # one mesh: zeros the system hands out untouched (no resident memory), not 8 bytes a triangle written
    part = (np.zeros(len(mesh.triangles), dtype=np.int64) if len(meshes) == 1
            else np.repeat(np.arange(len(meshes)), np.diff(offsets)))
    return Layout(mesh, mesh_report, charts, atlas, texels, part, timings)


def layer_lookup(atlas, mesh, triangle, bary):
    """UV of surface points in the three layers.

    Parameters
    ----------
    triangle : (k,) int
    bary : (k, 3) float

    Returns
    -------
    (k, 3, 2) float64: UV per layer (X, Y, Z).
    """
    uv = np.stack([atlas.axis_uv(axis, triangle) for axis in range(3)], axis=1)   # (k, 3 layers, 3 corners, 2)
    return np.einsum("kc,klcd->kld", bary, uv)
