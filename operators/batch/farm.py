"""The batch on a Dask cluster: one task per asset, each baked in a Blender process on a worker.

    batch(paths, output_dir=..., scheduler="tcp://HOST:8786")     # = batch PATH ... --scheduler tcp://HOST:8786

Dask's ``distributed`` is needed here only, imported when a scheduler is
given; the extension never needs it.  Each task is
:func:`.asset_process.bake_in_process`, sent by value, so a worker needs
Blender (or the ``bpy`` module) and this package's folder, not the package
installed in its own Python.  Inputs and outputs must be at the same paths
on every machine (a shared file system).  When a worker dies holding an
asset, the scheduler gives the asset to another worker; the bake it was
running dies with it (:func:`.asset_process._die_with_parent`, Linux), and
what it left half-written is removed when the batch ends.  Records come
back to this process, which keeps the stamps and the report as a local
batch does.
"""

import os
import uuid

from ...core.errors import SeamlessAOError
from ...core.other_processes.batch_plan import AssetRecord
from . import asset_process
from .asset_process import failed_record, partial_outputs

#: The package folder sent with each task (a worker's :data:`.asset_process.PACKAGE_VARIABLE` overrides it).
PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
#: Seconds to wait for the scheduler to answer.
CONNECT_SECONDS = 30
#: How to get Dask where a scheduler is asked for without it (docs/pipelines.md has the pins).
INSTALL_HINT = ("install Dask's distributed into the Python that runs the batch (python -m pip install "
                "'distributed==2026.8.0'; docs/pipelines.md)")


def distributed_module():
    """Dask's ``distributed``, or a :class:`SeamlessAOError` that says how to install it."""
    try:
        import cloudpickle
        import distributed
    except ImportError:
        raise SeamlessAOError("--scheduler needs Dask, which this Python does not have: " + INSTALL_HINT) from None
    # the task goes by value (see run_on_cluster): a worker need not have this package importable
    cloudpickle.register_pickle_by_value(asset_process)
    return distributed


def run_on_cluster(jobs, scheduler, timeout=None):
    """Bake ``jobs`` (worker job dicts, one per asset) on the Dask cluster at ``scheduler``; yield each
    asset's :class:`~...core.other_processes.batch_plan.AssetRecord` as its task ends, in the order they end.

    A task whose workers kept dying (Dask's ``allowed-failures``) or that failed outside the bake is
    reported failed with a sentence, and the others go on.  When the last record is out, what dead workers
    left half-written for these outputs is removed.

    Raises
    ------
    SeamlessAOError
        When Dask is missing or the scheduler cannot be reached.
    """
    distributed = distributed_module()
    try:
        client = distributed.Client(scheduler, timeout=CONNECT_SECONDS, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as error:
        raise SeamlessAOError("could not reach the Dask scheduler at {}: {}".format(scheduler, error)) from None
    batch_key = uuid.uuid4().hex[:8]

    def bake_there(job, package_root, timeout):
        # A local function: Dask's pickle refuses it and hands it to cloudpickle, which sends it, and
        # asset_process registered by value, as code; a module-level one would go by name, which neither the
        # scheduler nor a worker can import.
        return asset_process.bake_in_process(job, package_root, timeout)

    try:
        futures = {}
        for number, job in enumerate(jobs):
            # unique keys: two batches on one cluster never share a task, and a re-run bakes again
            key = "seamless-ao-{}-{}-{}".format(batch_key, number, os.path.basename(job["input"]))
            futures[client.submit(bake_there, job, PACKAGE_ROOT, timeout, key=key, pure=False)] = job
        for future in distributed.as_completed(futures, loop=client.loop):
            yield AssetRecord(**_task_record(future, futures[future], distributed))
    finally:
        client.close()
        for job in jobs:
            for partial in partial_outputs(job["output"]):
                _remove(partial)


def _task_record(future, job, distributed):
    """The record a task returned, or one that says why the task itself failed."""
    try:
        return future.result()
    except distributed.KilledWorker:
        return failed_record(job, "every Dask worker that took it died while baking it (Dask's allowed-failures): "
                             "the asset may crash Blender or need more memory than a worker has")
    except Exception as error:                                  # the task's own error, raised again here
        return failed_record(job, "the Dask task failed: {}: {}".format(type(error).__name__, error))


def _remove(path):
    try:
        os.remove(path)
    except FileNotFoundError:
        pass
