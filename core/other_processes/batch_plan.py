"""Batch bakes without Blender data: which files are assets, where each result goes, what is up to date.

The Blender side (``operators/batch/``) runs one worker process per asset;
everything it decides before and after that is here, as plain functions on
paths and dictionaries.

Outputs never leave the output folder: an output's name is made only of the
input's file name (never its folders), reduced to ``[A-Za-z0-9._-]``, and
checked to resolve inside the folder.  A re-run skips an asset whose output
is newer than the input and was made with the same settings; what settings
made each output is remembered in one stamp file per output folder.
"""

import dataclasses
import glob as globbing
import hashlib
import json
import os
import pathlib
import re

from ..errors import SeamlessAOError

#: File types a batch reads, and what it writes for each.
ASSET_SUFFIXES = (".blend", ".glb", ".gltf", ".obj", ".fbx", ".ply", ".stl")
OUTPUT_SUFFIX = {".blend": ".blend"}           # everything else becomes .glb
OUTPUT_TAG = "_ao"                             # chair.glb -> chair_ao.glb
STAMP_FILE = ".seamless_ao_batch.json"
#: What a worker writes before renaming it to its output (``chair_ao.glb.part1234.glb``): a worker that is
#: stopped or crashes leaves it behind, and it is never taken for an input.
PARTIAL = re.compile(r"\.part\d+$")
#: Bump when a change of the batch itself should redo every output.
BATCH_VERSION = 1
MAX_NAME = 96


@dataclasses.dataclass
class AssetRecord:
    """One asset's line in the batch report (``--report``); every field is JSON-ready.

    ``status`` is ``"baked"``, ``"skipped"`` (up to date) or ``"failed"`` (``error`` says why; with
    ``skipped`` true when the same input and settings failed before and were not tried again).
    ``seconds`` holds the worker's stages: ``load``, the bake's own (``charts``, ``atlas``, ``rays``,
    ``denoise`` ...), ``export`` and ``total``.
    """

    input: str
    output: str
    status: str = "failed"
    error: str = ""
    skipped: bool = False
    objects: list = dataclasses.field(default_factory=list)
    triangles: int = 0
    texels: int = 0
    rays: float = 0.0
    noise: float = 0.0
    seconds: dict = dataclasses.field(default_factory=dict)
    warnings: list = dataclasses.field(default_factory=list)

    def as_dict(self):
        return dataclasses.asdict(self)


def find_assets(paths, pattern="*"):
    """The asset files named by ``paths``, sorted and without repeats.

    Parameters
    ----------
    paths : iterable of str
        Files, folders (searched with their subfolders) or glob patterns
        (``assets/*.glb``).
    pattern : str
        Glob on file names applied inside folders (``*.glb``).

    Returns
    -------
    (assets, unreadable) : list of pathlib.Path (absolute), list of (str, str)
        ``unreadable`` holds each given path that matches nothing or names a
        file of a type the batch does not read, with one sentence saying so.
    """
    found, problems = {}, []
    for given in paths:
        path = pathlib.Path(given).expanduser()
        if path.is_dir():
            files = [p for p in sorted(path.rglob(pattern)) if p.is_file() and p.suffix.lower() in ASSET_SUFFIXES]
            if not files:
                problems.append((given, "no {} file matching '{}' in this folder".format(
                    "/".join(ASSET_SUFFIXES), pattern)))
        elif path.is_file():
            files = [path]
            if path.suffix.lower() not in ASSET_SUFFIXES:
                problems.append((given, "not a file type Seamless AO reads (it reads {})".format(
                    ", ".join(ASSET_SUFFIXES))))
                files = []
        else:
            files = [pathlib.Path(p) for p in sorted(globbing.glob(str(path), recursive=True))]
            files = [p for p in files if p.is_file() and p.suffix.lower() in ASSET_SUFFIXES]
            if not files:
                problems.append((given, "no such file or folder, and no asset matches it as a pattern"))
        for p in files:
            found.setdefault(str(p.resolve()), p.resolve())
    return sorted(found.values()), problems


def safe_stem(name):
    """A file-name stem made of ``[A-Za-z0-9._-]`` only, never starting with a dot or dash, never empty."""
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", name)
    stem = stem.lstrip(".-_")[:MAX_NAME].rstrip(".")
    return stem or "asset"


def plan_outputs(assets, output_dir=None):
    """Where each asset's result goes: ``{input: output}``, all absolute.

    Parameters
    ----------
    assets : list of pathlib.Path
    output_dir : path-like, optional
        One folder for every output; default: next to each input.

    Returns
    -------
    dict pathlib.Path -> pathlib.Path
        ``<safe stem>_ao.glb`` (``.blend`` for a .blend), inside
        ``output_dir``; inputs whose names would collide get a short hash of
        their full path appended.
    """
    base = pathlib.Path(output_dir).expanduser().resolve() if output_dir is not None else None
    wanted = {}
    for asset in assets:
        folder = base if base is not None else asset.parent.resolve()
        suffix = OUTPUT_SUFFIX.get(asset.suffix.lower(), ".glb")
        wanted[asset] = (folder, safe_stem(asset.stem) + OUTPUT_TAG, suffix)
    counts = {}
    for folder, stem, suffix in wanted.values():
        key = (folder, (stem + suffix).lower())
        counts[key] = counts.get(key, 0) + 1
    outputs = {}
    for asset, (folder, stem, suffix) in wanted.items():
        if counts[(folder, (stem + suffix).lower())] > 1:
            stem += "-" + hashlib.sha1(str(asset).encode()).hexdigest()[:8]
        output = folder / (stem + suffix)
        if output.resolve().parent != folder:
            raise SeamlessAOError("output {} would leave the folder {}".format(output, folder))
        outputs[asset] = output
    return outputs


def partial_output(output, pid):
    """Where worker ``pid`` writes ``output`` before renaming it (same folder and suffix)."""
    output = str(output)
    return "{}.part{}{}".format(output, pid, os.path.splitext(output)[1])


def remove_partial_output(output, pid):
    """Remove what worker ``pid`` left half-written for ``output``, if anything."""
    try:
        os.remove(partial_output(output, pid))
    except FileNotFoundError:
        pass


def drop_outputs(assets, output_dir=None):
    """``assets`` without earlier results: ``*_ao.glb`` and ``*_ao.blend`` files in ``output_dir`` or
    beside an input ``x.*`` that writes ``x_ao.*``, and what a stopped worker left half-written (see
    :data:`PARTIAL`).  So a re-run never bakes its own outputs."""
    base = pathlib.Path(output_dir).expanduser().resolve() if output_dir is not None else None
    sources = {(a.parent, safe_stem(a.stem)) for a in assets}
    kept = []
    for asset in assets:
        stem = asset.stem
        if PARTIAL.search(stem) and PARTIAL.sub("", stem).endswith(OUTPUT_TAG + asset.suffix):
            continue
        earlier_result = stem.endswith(OUTPUT_TAG) and asset.suffix.lower() in (".glb", ".blend") and (
            asset.parent == base or (asset.parent, stem[:-len(OUTPUT_TAG)]) in sources)
        if not earlier_result:
            kept.append(asset)
    return kept


def settings_digest(options):
    """A short fingerprint of everything that shapes an output (bake and export settings, flags)."""
    text = json.dumps({"batch": BATCH_VERSION, "options": options}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def read_stamps(folder):
    """``{output file name: stamp}`` remembered in ``folder`` (empty if none or unreadable)."""
    try:
        with open(pathlib.Path(folder) / STAMP_FILE, encoding="utf-8") as handle:
            stamps = json.load(handle)
        return stamps if isinstance(stamps, dict) else {}
    except (OSError, ValueError):
        return {}


def write_stamp(output, asset, digest, record):
    """Remember what made ``output`` (or why it failed), for the next run's :func:`previous_result`."""
    folder = pathlib.Path(output).parent
    stamps = read_stamps(folder)
    stat = os.stat(asset)
    stamps[pathlib.Path(output).name] = {
        "input": str(asset), "input_mtime_ns": stat.st_mtime_ns, "input_size": stat.st_size,
        "settings": digest, "status": record.status, "error": record.error}
    temporary = folder / (STAMP_FILE + ".tmp")
    with open(temporary, "w", encoding="utf-8") as handle:
        json.dump(stamps, handle, indent=1, sort_keys=True)
    os.replace(temporary, folder / STAMP_FILE)


def previous_result(asset, output, digest):
    """``None`` if ``asset`` must be baked, else the stamp of the run whose result still stands.

    A baked output stands when it exists, is at least as new as the input and
    was made with the same settings; a failure stands when the input (time
    and size) and the settings are the ones that failed, and no output exists
    (one that does was written after the failure was stamped: bake again to
    know which is true).
    """
    stamp = read_stamps(pathlib.Path(output).parent).get(pathlib.Path(output).name)
    if not stamp or stamp.get("settings") != digest or stamp.get("input") != str(asset):
        return None
    stat = os.stat(asset)
    if stamp.get("status") == "baked":
        if os.path.exists(output) and os.stat(output).st_mtime_ns >= stat.st_mtime_ns:
            return stamp
        return None
    if (stamp.get("input_mtime_ns") == stat.st_mtime_ns and stamp.get("input_size") == stat.st_size
            and not os.path.exists(output)):
        return stamp
    return None


def eta_seconds(done, total, elapsed):
    """Seconds left at the pace so far (0 when nothing is left, None before the first asset)."""
    if done >= total:
        return 0.0
    if done <= 0:
        return None
    return elapsed / done * (total - done)


def progress_line(done, total, record, elapsed):
    """``[3/6] baked chair.glb -> chair_ao.glb in 4.2 s, about 12 s left`` (one per finished asset)."""
    name = pathlib.Path(record.input).name
    if record.status == "failed":
        text = "failed {}{}: {}".format(name, " (as before)" if record.skipped else "", record.error)
    elif record.status == "skipped":
        text = "skipped {} (up to date: {})".format(name, pathlib.Path(record.output).name)
    else:
        text = "baked {} -> {} in {:.1f} s".format(name, pathlib.Path(record.output).name,
                                                   record.seconds.get("total", 0.0))
    left = eta_seconds(done, total, elapsed)
    if left is None or done >= total:
        tail = ""
    else:
        tail = ", about {:.0f} s left".format(left)
    return "seamless_ao: [{}/{}] {}{}".format(done, total, text, tail)
