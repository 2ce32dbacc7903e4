"""Bake a folder of assets: ``batch(paths, output_dir=None, jobs=None, ...) -> [AssetRecord]``.

The same as ``blender --background --command seamless_ao batch PATH ...``.
Each asset is baked in a worker process of its own (``jobs`` at a time), so
a crash or a refused mesh costs one asset, never the batch, and the cores
are used even where a bake runs on one.  Workers are Blender itself
(``bpy.app.binary_path --background --factory-startup --disable-autoexec``)
or, under the bpy module, the same Python; either way they load this package
from its own folder and never run anything an asset carries.  With a Dask
scheduler's address the workers are a cluster's instead (:mod:`.farm`).
"""

import dataclasses
import json
import os
import subprocess
import sys
import tempfile
import time

from ...core.errors import SeamlessAOError
from ...core.other_processes.batch_plan import (AssetRecord, drop_outputs, find_assets, plan_outputs, previous_result,
                                                progress_line, remove_partial_output, settings_digest, write_stamp)
from ...core.settings import BakeSettings, GltfSettings, gltf_fields
from ..adapters.processes import process_command, process_environment
from .asset_process import read_record, timed_out_record, write_worker_job
from .farm import run_on_cluster

REPORT_VERSION = 1
#: Where a batch's defaults differ from a bake's: the pieces of an asset occlude each other.
BATCH_DEFAULTS = {"use_scene_occluders": True}

def worker_command(job_path):
    """The command line of one worker (:func:`..adapters.processes.process_command`)."""
    return process_command("worker", job_path)


def worker_options(bake_settings, gltf, per_object=False):
    """What every worker's job holds besides its ``input`` and ``output``: the bake settings, the glTF
    settings (:class:`~...core.settings.GltfSettings`, one key each) and ``per_object``."""
    return dict(settings=dataclasses.asdict(bake_settings), per_object=bool(per_object), **dataclasses.asdict(gltf))


def batch(paths, output_dir=None, jobs=None, pattern="*", force=False, per_object=False, report=None, progress=None,
          timeout=None, scheduler=None, **settings):
    """Bake every asset found in ``paths``; returns one :class:`~..core.batch.AssetRecord` per asset.

    Parameters
    ----------
    paths : list of str
        Files, folders (searched with their subfolders) or glob patterns.
    output_dir : str, optional
        Where the results go (created if needed); default: next to each input.
    jobs : int, optional
        Worker processes at once; default: the number of cores.
    pattern : str
        File-name glob inside folders, e.g. ``"*.glb"``.
    force : bool
        Bake even assets whose output is up to date.
    per_object : bool
        One AO image per object instead of one per asset.
    report : str, optional
        Write a JSON report here (schema in the README).
    progress : callable(str), optional
        Called with one line per finished asset; default: print to stderr.
    timeout : float, optional
        Seconds an asset may take; a worker still running then is stopped
        and its asset reported failed.  Default: no limit.
    scheduler : str, optional
        The address of a Dask scheduler (``tcp://HOST:PORT``): one task per
        asset on its workers instead of ``jobs`` processes here (:mod:`.farm`;
        needs Dask's ``distributed``, docs/pipelines.md).
    **settings
        Any bake setting (:class:`~..core.settings.BakeSettings`), e.g.
        ``rays=32``; the others take their defaults, not a scene's, except
        ``use_scene_occluders``, on unless given: an asset's pieces occlude
        each other.  And any glTF setting
        (:class:`~..core.settings.GltfSettings`: ``uv_policy``,
        ``color_attribute``, ``texture_size``, ``texture_padding``,
        ``texture_packing``, ``texture_bit_depth``; docs/settings.md): where
        ``uv_policy`` is ``auto``, the record's warnings say why an object's own
        UV map could not hold the AO (:func:`~...core.export.uv_fitness.uv_fitness`).

    Raises
    ------
    SeamlessAOError
        For a bad setting, or when ``paths`` name no asset at all.
    """
    bake_settings, gltf = batch_settings(settings)
    jobs = _worker_count(jobs, scheduler)
    if timeout is not None and not timeout > 0:
        raise SeamlessAOError("timeout must be a number of seconds above 0 (got {!r})".format(timeout))
    progress = progress or (lambda line: print(line, file=sys.stderr, flush=True))

    assets, unreadable = find_assets(paths, pattern)
    assets = drop_outputs(assets, output_dir)
    if not assets:
        raise SeamlessAOError("no asset to bake: " + ("; ".join("{}: {}".format(*u) for u in unreadable)
                                                       or "the paths name none"))
    if output_dir is not None:
        os.makedirs(output_dir, exist_ok=True)
    outputs = plan_outputs(assets, output_dir)
    job_options = worker_options(bake_settings, gltf, per_object)
    digest = settings_digest(job_options)

    records = [AssetRecord(input=given, output="", error=sentence) for given, sentence in unreadable]
    total = len(assets) + len(records)
    started = time.perf_counter()
    for record in records:
        progress(progress_line(len(records), total, record, time.perf_counter() - started))
    queue, standing = _still_to_bake(assets, outputs, digest, force)
    for record in standing:
        records.append(record)
        progress(progress_line(len(records), total, record, time.perf_counter() - started))

    with tempfile.TemporaryDirectory(prefix="seamless_ao_batch_") as scratch:
        if scheduler is None:
            finished = _run_workers(queue, outputs, job_options, jobs, scratch, timeout)
        else:
            finished = run_on_cluster([dict(job_options, input=str(asset), output=str(outputs[asset]))
                                       for asset in queue], scheduler, timeout)
        for record in finished:
            records.append(record)
            write_stamp(record.output, record.input, digest, record)
            progress(progress_line(len(records), total, record, time.perf_counter() - started))
    if report is not None:
        write_report(report, records, job_options, time.perf_counter() - started)
    return records


def batch_settings(settings):
    """``(BakeSettings, GltfSettings)`` of a batch's keywords: the bake's defaults but
    :data:`BATCH_DEFAULTS`, the glTF's; an error for a setting a batch cannot take."""
    gltf_names = {f.name for f in gltf_fields()}
    given_gltf = {name: value for name, value in settings.items() if name in gltf_names}
    if given_gltf.get("color_attribute", "NONE") is None:        # the API's "no colour attribute"
        given_gltf["color_attribute"] = "NONE"
    bake_settings = BakeSettings.from_kwargs(**dict(BATCH_DEFAULTS, **{
        name: value for name, value in settings.items() if name not in gltf_names}))
    if bake_settings.save_image != "NONE":
        raise SeamlessAOError("save_image is not available in a batch: the AO goes into each output file (packed "
                              "into the .blend, embedded in the .glb), and files beside the inputs would leave "
                              "the output folder")
    return bake_settings, GltfSettings.from_kwargs(**given_gltf)


def _worker_count(jobs, scheduler):
    """Worker processes at once: ``jobs``, else one per core; an error for a count that is none, or beside
    a scheduler (whose workers decide)."""
    if scheduler is not None and jobs is not None:
        raise SeamlessAOError("give --jobs or --scheduler, not both: on a Dask cluster its workers decide how many "
                              "assets bake at once")
    if jobs is None:
        return os.cpu_count() or 1
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise SeamlessAOError("jobs must be a whole number of worker processes, at least 1 (got {!r}); leave it "
                              "out for one per core".format(jobs))
    return jobs


def _still_to_bake(assets, outputs, digest, force):
    """``(assets to bake, records of the others)``: an asset whose earlier result stands (its stamp: baked
    and up to date, or failed with the same input and settings) is not baked again unless ``force``."""
    queue, standing = [], []
    for asset in assets:
        stamp = None if force else previous_result(asset, outputs[asset], digest)
        if stamp is None:
            queue.append(asset)
        else:
            status = "skipped" if stamp["status"] == "baked" else "failed"
            standing.append(AssetRecord(input=str(asset), output=str(outputs[asset]), skipped=True, status=status,
                                        error=stamp["error"]))
    return queue, standing


def _run_workers(queue, outputs, job_options, jobs, scratch, timeout=None):
    """Yield each asset's record as its worker finishes, keeping ``jobs`` workers busy; a worker running
    longer than ``timeout`` seconds is killed."""
    queue = list(queue)
    running = []
    number = 0
    while queue or running:
        while queue and len(running) < jobs:
            asset = queue.pop(0)
            number += 1
            job = dict(job_options, input=str(asset), output=str(outputs[asset]))
            job_path, job = write_worker_job(job, scratch, number)
            log_path = os.path.join(scratch, "log{}.txt".format(number))
            with open(log_path, "w", encoding="utf-8") as log:
                process = subprocess.Popen(worker_command(job_path), stdout=log, stderr=subprocess.STDOUT,
                                           stdin=subprocess.DEVNULL, env=process_environment(scratch))
            running.append((process, job, log_path, time.perf_counter()))
        time.sleep(0.05)
        for entry in list(running):
            process, job, log_path, started = entry
            if process.poll() is None:                 # still running: stopped only if past the deadline
                if timeout is None or time.perf_counter() - started <= timeout:
                    continue
                process.kill()
                process.wait()
                remove_partial_output(job["output"], process.pid)   # what it was writing when stopped
                running.remove(entry)
                yield AssetRecord(**timed_out_record(job, timeout))
                continue
            running.remove(entry)
            yield AssetRecord(**read_record(job, process.returncode, log_path))


def write_report(path, records, job_options, seconds):
    """The JSON report: the settings, totals and one record per asset (README, "Pipelines")."""
    counts = {status: sum(r.status == status for r in records) for status in ("baked", "skipped", "failed")}
    data = {"version": REPORT_VERSION, "settings": job_options, "seconds": seconds, "counts": counts,
            "assets": [r.as_dict() for r in records]}
    with open(path, "w", encoding="utf-8") as handle:
        json.dump(data, handle, indent=1)
