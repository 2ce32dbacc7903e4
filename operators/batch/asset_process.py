"""One asset baked in a Blender process of its own: the command, the job file, the record it leaves.

The standard library only, and nothing of this package: a Dask worker runs
:func:`bake_in_process` (sent to it by value, :mod:`.farm`) without the
package being importable there.  The local batch (:mod:`.runner`) uses the
same command, job file and record reading for its own worker processes.

A record is an :class:`~...core.other_processes.batch_plan.AssetRecord` as a dict.
"""

import glob
import importlib.util
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile

#: Environment variables through which Blender would find the user's own folders (preferences, startup file,
#: scripts, extensions); a process of ours gets none of them.
USER_FOLDER_VARIABLES = ("BLENDER_USER_RESOURCES", "BLENDER_USER_CONFIG", "BLENDER_USER_SCRIPTS",
                         "BLENDER_USER_DATAFILES", "BLENDER_USER_EXTENSIONS")
#: On a farm worker: the Blender binary (or a Python with the ``bpy`` module) to bake with, and the folder of
#: the Seamless AO package, where they are not the defaults (``blender`` on the PATH; the client's folder).
BLENDER_VARIABLE = "SEAMLESS_AO_BLENDER"
PACKAGE_VARIABLE = "SEAMLESS_AO_PACKAGE"
#: Where the launcher sits in the package folder.
LAUNCHER_PATH = ("operators", "launchers", "launch.py")


def launch_command(binary, launcher, *arguments):
    """The command line that runs ``launcher`` with ``arguments``: a background Blender with factory settings,
    no auto-run scripts and exit code 1 on a Python error, or, where ``binary`` is a Python (the ``bpy``
    module), that Python."""
    if os.path.basename(binary).startswith("python"):
        return [binary, str(launcher), *map(str, arguments)]
    return [binary, "--background", "--factory-startup", "--disable-autoexec", "--python-exit-code", "1",
            "--python", str(launcher), "--", *map(str, arguments)]


def user_folders_moved(environment, scratch):
    """``environment`` without Blender's user-folder variables, its user resources in ``scratch``."""
    kept = {name: value for name, value in environment.items() if name not in USER_FOLDER_VARIABLES}
    return dict(kept, BLENDER_USER_RESOURCES=os.path.join(scratch, "blender_user"))


def write_worker_job(job, scratch, number):
    """Write ``job`` (a dict) with a record path beside it into ``scratch``; returns (job path, job)."""
    job = dict(job, record=os.path.join(scratch, "record{}.json".format(number)))
    job_path = os.path.join(scratch, "job{}.json".format(number))
    with open(job_path, "w", encoding="utf-8") as handle:
        json.dump(job, handle)
    return job_path, job


def failed_record(job, sentence, seconds=None):
    """The record of an asset that was not baked, ``sentence`` saying why."""
    return dict(input=job["input"], output=job["output"], status="failed", error=sentence,
                seconds={} if seconds is None else {"total": float(seconds)})


def timed_out_record(job, timeout):
    return failed_record(job, "stopped after {:g} s (--timeout); the asset took longer".format(timeout), timeout)


def read_record(job, returncode, log_path):
    """The record the worker process wrote, or one that says how it died (with its log's last line)."""
    try:
        with open(job["record"], encoding="utf-8") as handle:
            record = json.load(handle)
        if isinstance(record, dict):
            return record
    except (OSError, ValueError):
        pass
    with open(log_path, encoding="utf-8", errors="replace") as handle:
        lines = [line.strip() for line in handle if line.strip()]
    return failed_record(job, "the worker stopped with exit code {}{}".format(
        returncode, " ({})".format(lines[-1]) if lines else ""))


def partial_outputs(output):
    """What stopped workers left half-written for ``output`` (``NAME.partPID.EXT``, see
    core/other_processes/batch_plan.py)."""
    extension = os.path.splitext(str(output))[1]
    return glob.glob(glob.escape(str(output)) + ".part[0-9]*" + glob.escape(extension))


def without_worker_limits(environment):
    """``environment`` without what a Dask nanny sets for its worker (``distributed.nanny.pre-spawn-environ``:
    one OpenMP, MKL and OpenBLAS thread, for tasks that share the worker's process): the bake runs in a process
    of its own and uses the machine's cores as a local batch's worker does (a throwaway run of
    bench_farm.py with one worker: 3.65 s per asset with the limits, 2.78 s without; local: 2.82 s)."""
    try:
        import dask
        limits = dask.config.get("distributed.nanny.pre-spawn-environ", {}) or {}
    except ImportError:
        return environment
    return {name: value for name, value in environment.items()
            if name not in limits or value != str(limits[name])}


def farm_binary():
    """This machine's way to run Blender for a farm task: :data:`BLENDER_VARIABLE`, else ``blender`` on the
    PATH, else this Python where it has the ``bpy`` module; None when there is none."""
    given = os.environ.get(BLENDER_VARIABLE)
    if given:
        return given if os.path.isfile(given) else None
    found = shutil.which("blender")
    if found:
        return found
    return sys.executable if importlib.util.find_spec("bpy") is not None else None


def _die_with_parent():
    """In the child before it runs (Linux): killed when the worker that started it dies, so a dead Dask
    worker leaves no bake running that the scheduler has given to another worker."""
    try:
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)       # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def bake_in_process(job, package_root, timeout=None):
    """Bake one asset on this machine (a Dask worker's task): run the package's batch worker on ``job`` in a
    Blender process of its own and return its record.

    Parameters
    ----------
    job : dict
        The worker's job (core settings, export options, ``input``, ``output``), without the record path.
    package_root : str
        The package's folder on the machine that sent the task; :data:`PACKAGE_VARIABLE` overrides it.
    timeout : float, optional
        Seconds the asset may take.

    Returns
    -------
    dict
        The asset's record; a machine without Blender or without the package fails the asset with a
        sentence saying which and how to give it one.
    """
    host = socket.gethostname()
    root = os.environ.get(PACKAGE_VARIABLE) or package_root
    launcher = os.path.join(root, *LAUNCHER_PATH)
    if not os.path.isfile(launcher):
        return failed_record(job, "the Dask worker on {} has no Seamless AO at {}: copy the extension there or set "
                             "{} to its folder on that machine".format(host, root, PACKAGE_VARIABLE))
    binary = farm_binary()
    if binary is None:
        return failed_record(job, "the Dask worker on {} found no Blender: put blender on its PATH, set {} to the "
                             "Blender binary, or run the worker with a Python that has the bpy module".format(
                                 host, BLENDER_VARIABLE))
    with tempfile.TemporaryDirectory(prefix="seamless_ao_task_") as scratch:
        job_path, job = write_worker_job(job, scratch, 1)
        log_path = os.path.join(scratch, "log.txt")
        with open(log_path, "w", encoding="utf-8") as log:
            process = subprocess.Popen(
                launch_command(binary, launcher, "worker", job_path), stdout=log, stderr=subprocess.STDOUT,
                stdin=subprocess.DEVNULL, env=without_worker_limits(user_folders_moved(os.environ, scratch)),
                preexec_fn=_die_with_parent if sys.platform.startswith("linux") else None)
            try:
                process.wait(timeout)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
                for partial in partial_outputs(job["output"]):
                    os.remove(partial)
                return timed_out_record(job, timeout)
        return read_record(job, process.returncode, log_path)
