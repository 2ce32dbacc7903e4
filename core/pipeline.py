"""The core steps chained: mesh -> charts -> atlas -> texels -> AO image.

Each step is also callable alone (see the modules); this module only orders
them, times them and passes progress and cancellation through.
"""

import time
from dataclasses import dataclass, field

import numpy as np

from .adjacency import face_adjacency
from .atlas import chart_plane_area, estimate_density, pack_charts
from .clustering import cluster_faces, make_injective
from .errors import SeamlessAOError
from .mesh import require_faces
from .raster import rasterise

#: Distant parts of one chart must stay this many texels apart (bilinear reads 1).
SEPARATION_TEXELS = 3.0


@dataclass
class Layout:
    """Everything about where AO is stored, before any ray is cast."""

    mesh: object
    topology: object
    charts: object
    atlas: object
    texels: object
    timings: dict = field(default_factory=dict)


def build_layout(mesh, compare_angle=60.0, image_size=1024, density=None, padding=4):
    """Charts, atlas and texels for a :class:`~.mesh.TriangleMesh`.

    Parameters
    ----------
    mesh : TriangleMesh
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
    require_faces(mesh)
    timings = {}
    start = time.perf_counter()
    topology = face_adjacency(mesh)
    charts = cluster_faces(mesh, topology, compare_angle)
    timings["charts"] = time.perf_counter() - start

    start = time.perf_counter()
    area = chart_plane_area(mesh, charts)
    expected = density if density is not None else estimate_density(area, image_size)
    # A second pass keeps distant parts of a chart apart by a few texels, so
    # filtering at a chart's edge never mixes in AO from another surface.
    charts = make_injective(mesh, topology, charts, margin=SEPARATION_TEXELS / expected)
    atlas = pack_charts(mesh, topology, charts, padding=padding,
                        image_size=None if density is not None else image_size, density=density)
    charts = atlas.charts
    timings["pack"] = time.perf_counter() - start

    start = time.perf_counter()
    texels = rasterise(atlas, mesh, padding=padding)
    timings["rasterise"] = time.perf_counter() - start
    if not len(texels):
        raise SeamlessAOError("No texel landed on the mesh; raise the image size or texel density")
    return Layout(mesh, topology, charts, atlas, texels, timings)


def estimated_bytes(texel_count, image_pixels):
    """Peak memory estimate of a bake, in bytes (dense maps + per-texel arrays + batches)."""
    return int(image_pixels * 10 + texel_count * 40 + 512 * 2**20)


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
