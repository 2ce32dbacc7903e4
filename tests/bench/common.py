"""Helpers shared by the benchmark scripts: timing, peak memory, tables."""

import resource
import sys
import time
import tracemalloc

sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parent.parent / "support"))

import package  # noqa: E402  (imports bpy and the add-on as ``seamless_ao``)

import bpy  # noqa: E402
from accuracy import reference_ao, surface_samples  # noqa: E402
from blender_scenes import suzanne  # noqa: E402
from seamless_ao.core.settings import BakeSettings  # noqa: E402
from seamless_ao.operators.mesh_data import read_triangles  # noqa: E402


class Stopwatch:
    """``with Stopwatch() as sw: ...`` then ``sw.seconds``; also tracks peak numpy memory."""

    def __init__(self, trace_memory=True):
        self.trace_memory = trace_memory
        self.seconds = 0.0
        self.peak_mb = 0.0

    def __enter__(self):
        if self.trace_memory:
            tracemalloc.start()
        self.start = time.perf_counter()
        return self

    def __exit__(self, *exc):
        self.seconds = time.perf_counter() - self.start
        if self.trace_memory:
            self.peak_mb = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.stop()
        return False


def process_peak_mb():
    """Peak resident memory of this process so far, MB (Linux ru_maxrss is KB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def markdown_table(headers, rows):
    """A Markdown table as one string."""
    lines = ["| " + " | ".join(headers) + " |", "|" + "|".join("---" for _ in headers) + "|"]
    for row in rows:
        lines.append("| " + " | ".join(str(c) for c in row) + " |")
    return "\n".join(lines)


def suzanne_with_reference(points=2000, seed=5, rays=4096):
    """A factory scene with Suzanne subdivided twice and the add-on registered, and the plain reference
    (tests/support/plain_reference.py) at ``points`` visible surface points: what the ray-setting benchmarks
    compare against.

    Returns ``ob, loops, triangle, bary, normals, reference``.
    """
    bpy.ops.wm.read_factory_settings(use_empty=True)
    package.seamless_ao.register()
    ob = suzanne(2)
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals = surface_samples(mesh, points, seed=seed)
    reference = reference_ao(ob, mesh, triangle, bary, normals, rays=rays, settings=BakeSettings())
    return ob, loops, triangle, bary, normals, reference
