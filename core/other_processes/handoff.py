"""A bake handed to another process and its result handed back, as files in one folder.

    write_job(folder, meshes, matrices, occluders, settings, shown)          # the window's Blender
    meshes, matrices, occluders, settings, shown = read_job(folder)          # the background process ...
    write_progress(folder, 0.4, "Casting rays: 31%")                  # ... while it bakes
    write_outcome(folder, pipeline.result, len(meshes))               # ... or write_failure(folder, sentence)
    outcome = read_outcome(folder)                                    # the window's Blender again

Arrays go as ``.npy`` files (each input mesh's UVs one file per axis, read when that mesh is written, so
a million-triangle bake never holds them all twice), numbers and sentences as JSON.  Progress is one
line, replaced whole, so a reader never sees half of it.
"""

import dataclasses
import json
import os

import numpy as np

from ..mesh.triangle_mesh import TriangleMesh
from ..pipeline import LayerByLayer
from ..settings import BakeSettings

JOB = "job.json"
PROGRESS = "progress.txt"
OUTCOME = "outcome.json"
FAILURE = "failure.json"
MESH_ARRAYS = ("positions", "triangles", "triangle_face", "normals_as_read")
#: What a mesh carries where its reader knew it (None otherwise).
OPTIONAL_MESH_ARRAYS = ("vertex_island", "side_edge")
SURFACE_ARRAYS = ("positions", "corner_vert", "loop_start")


def _save(folder, name, array):
    np.save(os.path.join(folder, name + ".npy"), np.ascontiguousarray(array), allow_pickle=False)


def _load(folder, name):
    return np.load(os.path.join(folder, name + ".npy"), allow_pickle=False)


def _replace(folder, name, text):
    """Write ``text`` to ``name`` whole: a reader sees the old file or the new one, never half of it."""
    path = os.path.join(folder, name)
    with open(path + ".part", "w", encoding="utf-8") as handle:
        handle.write(text)
    os.replace(path + ".part", path)


def _write_json(folder, name, data):
    _replace(folder, name, json.dumps(data))


def _read_json(folder, name):
    with open(os.path.join(folder, name), encoding="utf-8") as handle:
        return json.load(handle)


def write_job(folder, meshes, matrices, occluders, settings, shown=None):
    """Write a bake's input.

    Parameters
    ----------
    folder : str, an existing folder
    meshes : list of TriangleMesh or MeshArrays (read as it was: the process works out the rest)
    matrices : list of (4, 4) float, world matrices
    occluders : list (one per mesh) of lists of ``(positions (v, 3) float64, triangles (t, 3) int64)``,
        world geometry near that mesh
    settings : BakeSettings
    shown : list (one per mesh) of None or ``(positions, corner_vert, loop_start)``, optional: another surface
        the mesh shows (:class:`..pipeline.BakePipeline`'s ``shown``)
    """
    shown = list(shown) if shown is not None else [None] * len(meshes)
    for part, surface in enumerate(shown):
        for name, array in zip(SURFACE_ARRAYS, surface or ()):
            _save(folder, "shown{}_{}".format(part, name), array)
    for part, mesh in enumerate(meshes):
        for name in MESH_ARRAYS:
            _save(folder, "mesh{}_{}".format(part, name), getattr(mesh, name))
        for name in OPTIONAL_MESH_ARRAYS:
            if getattr(mesh, name) is not None:
                _save(folder, "mesh{}_{}".format(part, name), getattr(mesh, name))
        _save(folder, "matrix{}".format(part), np.asarray(matrices[part], dtype=np.float64))
        for number, (positions, triangles) in enumerate(occluders[part]):
            _save(folder, "occluder{}_{}_positions".format(part, number), positions)
            _save(folder, "occluder{}_{}_triangles".format(part, number), triangles)
    _write_json(folder, JOB, {"settings": dataclasses.asdict(settings), "face_counts": [m.face_count for m in meshes],
                              "given": [[name for name in OPTIONAL_MESH_ARRAYS if getattr(m, name) is not None]
                                        for m in meshes],
                              "occluders": [len(near) for near in occluders],
                              "shown": [surface is not None for surface in shown]})


def read_job(folder):
    """``(meshes, matrices, occluders, settings, shown)`` as :func:`write_job` was given them."""
    job = _read_json(folder, JOB)
    meshes, matrices, occluders = [], [], []
    for part, face_count in enumerate(job["face_counts"]):
        arrays = {name: _load(folder, "mesh{}_{}".format(part, name)) for name in MESH_ARRAYS}
        for name in job["given"][part]:
            arrays[name] = _load(folder, "mesh{}_{}".format(part, name))
        mesh = TriangleMesh(face_count=face_count, **arrays)
        meshes.append(mesh)
        matrices.append(_load(folder, "matrix{}".format(part)))
        occluders.append([(_load(folder, "occluder{}_{}_positions".format(part, number)),
                           _load(folder, "occluder{}_{}_triangles".format(part, number)))
                          for number in range(job["occluders"][part])])
    shown = [tuple(_load(folder, "shown{}_{}".format(part, name)) for name in SURFACE_ARRAYS) if given else None
             for part, given in enumerate(job["shown"])]
    return meshes, matrices, occluders, BakeSettings.from_kwargs(**job["settings"]), shown


def write_progress(folder, fraction, message):
    """Replace the progress line: ``fraction`` in [0, 1] and what is being done."""
    _replace(folder, PROGRESS, "{:.6f}\t{}".format(fraction, message))


def read_progress(folder):
    """``(fraction, message)`` of the last :func:`write_progress`, or None before the first."""
    try:
        with open(os.path.join(folder, PROGRESS), encoding="utf-8") as handle:
            fraction, message = handle.read().split("\t", 1)
    except (OSError, ValueError):
        return None
    return float(fraction), message


def outcome_numbers(result):
    """What the report says of a :class:`..pipeline.BakeResult`, as plain numbers and sentences."""
    layout = result.layout
    return {"texels": int(result.texels), "rays": int(result.rays), "noise": float(result.noise),
            "caster": result.caster, "timings": {k: float(v) for k, v in result.timings.items()},
            "warnings": list(result.warnings), "width": int(layout.atlas.width), "height": int(layout.atlas.height),
            "utilisation": float(layout.atlas.utilisation), "density": float(layout.atlas.density),
            "charts": int(layout.charts.count), "mesh_problems": list(layout.mesh_report.problems())}


def write_outcome(folder, result, part_count):
    """Write what the window's Blender writes into Blender data: the image, each input mesh's UVs in
    AO_X, AO_Y and AO_Z and those of the surface it shows (if given), and :func:`outcome_numbers`.  The JSON
    goes last: its presence means done (:func:`outcome_written`)."""
    _save(folder, "image", result.image)
    for part in range(part_count):
        for axis, uv in enumerate(result.part_axis_uv(part)):
            _save(folder, "uv{}_{}".format(part, axis), uv)
        if result.part_shown_uv(part) is not None:
            _save(folder, "shown_uv{}".format(part), result.part_shown_uv(part))
    _write_json(folder, OUTCOME, outcome_numbers(result))


@dataclasses.dataclass
class HandedBack:
    """A bake's outcome read back: ``image`` (h, w) float32, ``numbers`` (:func:`outcome_numbers`), and
    :meth:`part_axis_uv` read from its files when asked."""

    folder: str
    image: np.ndarray
    numbers: dict

    def part_axis_uv(self, part):
        """Input mesh ``part``'s triangles' UVs in AO_X, AO_Y and AO_Z: three (k, 3, 2) float32 (as the bake
        wrote them, :meth:`..pipeline.BakeResult.part_axis_uv`), each read from its file when asked for
        (:class:`..pipeline.LayerByLayer`)."""
        return LayerByLayer(lambda axis: _load(self.folder, "uv{}_{}".format(part, axis)))

    def part_shown_uv(self, part):
        """(3, l, 2) float32 or None: see :meth:`..pipeline.BakeResult.part_shown_uv`."""
        if not os.path.exists(os.path.join(self.folder, "shown_uv{}.npy".format(part))):
            return None
        return _load(self.folder, "shown_uv{}".format(part))


def outcome_written(folder):
    """Whether :func:`write_outcome` has finished."""
    return os.path.exists(os.path.join(folder, OUTCOME))


def read_outcome(folder):
    """The :class:`HandedBack` outcome (once :func:`outcome_written`)."""
    return HandedBack(folder, _load(folder, "image"), _read_json(folder, OUTCOME))


def write_failure(folder, sentence, expected=True):
    """Say why the bake stopped: ``expected`` for the user's sentence (a refused mesh or setting), not for a
    fault of ours (its traceback is in the process's log)."""
    _write_json(folder, FAILURE, {"sentence": sentence, "expected": bool(expected)})


def read_failure(folder):
    """``(sentence, expected)`` of :func:`write_failure`, or None."""
    try:
        failure = _read_json(folder, FAILURE)
    except (OSError, ValueError):
        return None
    return failure["sentence"], failure["expected"]
