"""Where the AO will be stored: mesh -> charts -> atlas -> texels, chained and timed (:func:`build_layout`).

Each step is also callable alone (see the modules); this module only orders
them and times them.  The rays are :mod:`.job`'s, the finished image :mod:`.fill`'s.
"""

import time
from dataclasses import dataclass, field

import numpy as np

from .adjacency import Topology, face_adjacency
from .atlas import chart_plane_area, estimate_density, pack_charts
from .clustering import Charts, cut_long_charts, make_injective, signed_axis_clusters
from .errors import SeamlessAOError
from .mesh import MeshReport, TriangleMesh, require_faces
from .raster import rasterise

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

    mesh: object
    topology: object
    charts: object
    atlas: object
    texels: object
    part_of_triangle: np.ndarray = None
    timings: dict = field(default_factory=dict)

    def part_of_texel(self, selection=slice(None)):
        """(k,) int: input mesh of each texel."""
        return self.part_of_triangle[self.atlas.member_triangle[self.texels.member[selection]]]


def build_layout(meshes, compare_angle=60.0, image_size=1024, density=None, padding=4):
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

    Returns
    -------
    Layout
    """
    meshes = [meshes] if isinstance(meshes, TriangleMesh) else list(meshes)
    for mesh in meshes:
        require_faces(mesh)
    timings = {}
    start = time.perf_counter()
    topologies = [face_adjacency(mesh) for mesh in meshes]
    charts = [signed_axis_clusters(mesh, topology, compare_angle) for mesh, topology in zip(meshes, topologies)]
    timings["charts"] = time.perf_counter() - start

    start = time.perf_counter()
    area = sum(chart_plane_area(mesh, c) for mesh, c in zip(meshes, charts))
    expected = density if density is not None else estimate_density(area, image_size)
    # One injectivity pass with a margin: it splits folds (what cluster_faces
    # does) and also keeps distant parts of a chart a few texels apart, so
    # filtering at a chart's edge never mixes in AO from another surface.
    charts = [make_injective(mesh, topology, c, margin=SEPARATION_TEXELS / expected)
              for mesh, topology, c in zip(meshes, topologies, charts)]
    # no chart longer than a quarter of the image at the expected density (charts are never rotated)
    longest = (image_size / 4 if density is None else LONGEST_CHART_TEXELS) / expected
    charts = [cut_long_charts(mesh, c, longest) for mesh, c in zip(meshes, charts)]
    timings["injectivity"] = time.perf_counter() - start
    start = time.perf_counter()
    mesh, offsets = TriangleMesh.concatenate(meshes) if len(meshes) > 1 else (meshes[0], np.array([0, len(meshes[0].triangles)]))
    topology = merge_topologies(meshes, topologies) if len(meshes) > 1 else topologies[0]
    charts = merge_charts(charts) if len(meshes) > 1 else charts[0]
    atlas = pack_charts(mesh, topology, charts, padding=padding,
                        image_size=None if density is not None else image_size, density=density)
    charts = atlas.charts
    timings["pack"] = time.perf_counter() - start

    start = time.perf_counter()
    texels = rasterise(atlas, mesh, padding=atlas.padding)
    timings["rasterise"] = time.perf_counter() - start
    if not len(texels):
        raise SeamlessAOError("No texel landed on the mesh; raise the image size or texel density")
    part = np.repeat(np.arange(len(meshes)), np.diff(offsets))
    return Layout(mesh, topology, charts, atlas, texels, part, timings)


def merge_topologies(meshes, topologies):
    """One :class:`~.adjacency.Topology` for :meth:`TriangleMesh.concatenate`'d meshes."""
    welded_offsets = np.cumsum([0] + [int(t.welded.max()) + 1 if len(t.welded) else 0 for t in topologies])
    face_offsets = np.cumsum([0] + [m.face_count for m in meshes])
    report = MeshReport(**{
        name: sum(getattr(t.report, name) for t in topologies) for name in MeshReport.__dataclass_fields__})
    return Topology(
        welded=np.concatenate([t.welded + o for t, o in zip(topologies, welded_offsets)]),
        welded_triangles=np.concatenate([t.welded_triangles + o for t, o in zip(topologies, welded_offsets)]),
        face_edges=np.concatenate([t.face_edges + o for t, o in zip(topologies, face_offsets)]),
        report=report,
    )


def merge_charts(parts):
    """One :class:`~.clustering.Charts` for several meshes' charts (ids offset, never shared)."""
    offsets = np.cumsum([0] + [c.count for c in parts])
    return Charts(
        chart_of_face=np.concatenate([np.where(c.chart_of_face >= 0, c.chart_of_face + o, -1)
                                      for c, o in zip(parts, offsets)]),
        chart_axis=np.concatenate([c.chart_axis for c in parts]),
        dominant_axis=np.concatenate([c.dominant_axis for c in parts]),
        splits=sum(c.splits for c in parts),
    )


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
    uv = atlas.layer_uv()[triangle]                     # (k, 3 layers, 3 corners, 2)
    return np.einsum("kc,klcd->kld", bary, uv)
