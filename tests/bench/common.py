"""Helpers shared by the benchmark scripts: timing, peak memory, tables, and the page each writes.

A benchmark prints its results with :func:`say` and ends with :func:`finish`,
which writes what it said to ``docs/bench/<script>.md`` under a line naming
the script, its arguments, the machine, Blender and the commit;
``make bench`` then assembles those pages into ``docs/benchmarks.md``
(``tests/bench/assemble.py``).  Every figure in docs/ comes from such a page.
"""

import datetime
import json
import os
import pathlib
import platform
import subprocess
import sys
import time
import tracemalloc

import numpy as np

sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parent.parent / "support"))

import package  # noqa: E402  (imports bpy and the add-on as ``seamless_ao``)

import bpy  # noqa: E402
from accuracy import reference_ao, surface_samples  # noqa: E402
from blender_scenes import suzanne  # noqa: E402
from process_memory import process_peak_mb, resident_mb  # noqa: E402,F401  (the benches' memory figures)
from seams import point_normals  # noqa: E402
from seamless_ao.core.settings import BakeSettings  # noqa: E402
from seamless_ao.operators.adapters.mesh_data import read_triangles  # noqa: E402


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


ROOT = pathlib.Path(__file__).resolve().parents[2]
#: Where each benchmark writes its page.
PAGES = ROOT / "docs" / "bench"
_said = []


def say(text=""):
    """Print ``text`` and keep it for the benchmark's page."""
    print(text, flush=True)
    _said.append(str(text))


def machine():
    """This machine, Blender and the device Cycles bakes on, in one phrase."""
    return "{} ({} cores), Blender {}, {}".format(platform.processor() or platform.machine(), os.cpu_count(),
                                                 bpy.app.version_string, cycles_device_phrase())


def cycles_device_phrase():
    """Where Cycles bakes (ours and Blender's own route alike), as Cycles' preferences say."""
    from seamless_ao.operators.adapters.cycles_device import cycles_device
    if cycles_device()[0] == "CPU":
        return "Cycles on the CPU"
    preferences = bpy.context.preferences.addons["cycles"].preferences
    return "Cycles on {} ({})".format(preferences.compute_device_type, ", ".join(
        device.name for device in preferences.devices if device.use and device.type != "CPU"))


def use_gpu(kind):
    """Set Cycles' preferences as a user with GPUs of type ``kind`` (CUDA, OPTIX, HIP, ONEAPI, METAL) would:
    every such device on.  Both bakers' Cycles then bake on them; ends the benchmark with a sentence where
    this machine has none."""
    from seamless_ao.operators.adapters.cycles_device import apply_device_preference
    preferences = bpy.context.preferences.addons["cycles"].preferences
    try:
        preferences.compute_device_type = kind
    except TypeError:
        raise SystemExit("this Blender's Cycles knows no device type {!r}".format(kind))
    preferences.refresh_devices()
    found = [device.id for device in preferences.devices if device.type == kind]
    if not found:
        raise SystemExit("no {} device on this machine: the benchmark would run on the CPU".format(kind))
    apply_device_preference({"type": kind, "use": found})


def commit():
    """The commit the tree stands at (with ``+`` when files differ from it)."""
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True)
    return (head.stdout.strip() or "unknown") + ("+" if dirty.stdout.strip() else "")


def page_title(doc):
    """A benchmark's title: the first line of its docstring, without "Benchmark: "."""
    return doc.strip().splitlines()[0].replace("Benchmark: ", "").rstrip(".")


def page_method(doc):
    """What a benchmark does, from its docstring: the paragraphs after the title and the usage lines."""
    paragraphs = [p for p in doc.strip().split("\n\n")[1:] if not all(
        line.startswith("    ") for line in p.splitlines() if line.strip())]
    return [" ".join(p.split()) for p in paragraphs]


def finish(script, doc, status=0):
    """Write what the benchmark said to ``docs/bench/<script>.md``, under its title, the line naming the
    command, machine, Blender and commit, and its method (its docstring); then end the process (see
    ``package.hard_exit``)."""
    name = pathlib.Path(script).stem
    command = " ".join(["tests/bench/{}.py".format(name)] + sys.argv[1:])
    header = ["## {}".format(page_title(doc)), "",
              "*Written by `{}` on {}, commit {}, {}.*".format(
                  command, machine(), commit(), datetime.date.today().isoformat()), ""]
    for paragraph in page_method(doc):
        header += [paragraph, ""]
    if status == 0 and _said:
        PAGES.mkdir(parents=True, exist_ok=True)
        (PAGES / (name + ".md")).write_text("\n".join(header + _said).rstrip() + "\n")
        print("wrote", (PAGES / (name + ".md")).relative_to(ROOT))
    package.hard_exit(status)


def print_result(value):
    """Hand ``value`` (JSON) to the bench that started this process (:func:`child_result`)."""
    print(RESULT + json.dumps(value), flush=True)


def child_result(script, *arguments, timeout=3600, python=None):
    """Run the bench ``script`` with ``arguments`` in a process of its own (of ``python``, by default this one's
    interpreter: another Blender's virtualenv runs it in that Blender); what it handed back with
    :func:`print_result` (its last such line).  Raises RuntimeError, with the end of its stderr, where it
    failed or handed back nothing."""
    proc = subprocess.run([str(python or sys.executable), str(pathlib.Path(script).resolve()), *arguments],
                          capture_output=True, text=True, timeout=timeout)
    lines = [line for line in proc.stdout.splitlines() if line.startswith(RESULT)]
    if proc.returncode != 0 or not lines:
        raise RuntimeError(proc.stderr.strip()[-2000:] or "?")
    return json.loads(lines[-1][len(RESULT):])


#: What starts the line a bench's child process hands its result back on.
RESULT = "RESULT "


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


def cached_surface_samples(mesh, count, seed, path):
    """:func:`accuracy.surface_samples`, kept in ``path`` (.npz) once chosen: choosing them tests each candidate
    against every triangle (minutes on a million triangles).  ``path`` must name the mesh and the sampling's
    code, as report.py's ``mesh_key`` does; the normals come from the mesh each time, as there."""
    if not path.exists():
        triangle, bary, normals = surface_samples(mesh, count, seed=seed)
        np.savez(path, triangle=triangle, bary=bary)
        return triangle, bary, normals
    with np.load(path) as saved:
        triangle, bary = saved["triangle"], saved["bary"]
    return triangle, bary, point_normals(mesh, triangle, bary)
