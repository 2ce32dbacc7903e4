"""A real Dask cluster on the loopback address for the farm tests and bench: ``dask scheduler`` and ``dask
worker`` processes of the virtualenv's own Dask (requirements/farm.txt).

    with dask_cluster(folder, workers=2) as (address, client):
        seamless_ao.batch(paths, scheduler=address, ...)
"""

import contextlib
import json
import os
import pathlib
import subprocess
import sys
import time

#: Seconds to wait for the cluster to come up, and for what the tests poll for.
PATIENCE = 120


def wait_for(condition, what, patience=PATIENCE):
    """Poll ``condition()`` until it is true; an AssertionError naming ``what`` after ``patience`` seconds."""
    deadline = time.monotonic() + patience
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError("waited {} s for {}".format(patience, what))
        time.sleep(0.05)


def _written_address(scheduler_file):
    """The address in the scheduler's file, or None while the file is missing or not yet whole."""
    try:
        return json.loads(scheduler_file.read_text())["address"]
    except (FileNotFoundError, ValueError, KeyError):
        return None


@contextlib.contextmanager
def dask_cluster(folder, workers=2, environment=None):
    """A scheduler and ``workers`` workers (one thread each, with a nanny) on 127.0.0.1, logging into
    ``folder``; yields ``(address, client)``, a ``distributed.Client`` of the test's own."""
    import distributed
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    dask = str(pathlib.Path(sys.executable).with_name("dask"))
    scheduler_file = folder / "scheduler.json"
    logs, processes = [], []

    def start(*arguments):
        log = open(folder / "{}.log".format(len(processes)), "w")
        logs.append(log)
        processes.append(subprocess.Popen([dask, *arguments], stdout=log, stderr=subprocess.STDOUT,
                                          stdin=subprocess.DEVNULL, env=dict(os.environ, **(environment or {})),
                                          cwd=str(folder)))

    start("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard", "--scheduler-file", str(scheduler_file))
    try:
        # the scheduler creates the file before it has written it: wait for an address that reads whole
        wait_for(lambda: _written_address(scheduler_file) is not None, "the scheduler's address")
        address = _written_address(scheduler_file)
        for number in range(workers):
            name = "worker{}".format(number + 1)
            start("worker", address, "--name", name, "--nthreads", "1", "--host", "127.0.0.1", "--no-dashboard",
                  "--local-directory", str(folder / name))
        client = distributed.Client(address, timeout=PATIENCE, set_as_default=False)
        try:
            wait_for(lambda: len(client.scheduler_info()["workers"]) == workers, "{} workers".format(workers))
            yield address, client
        finally:
            client.close()
    finally:
        for process in processes[::-1]:
            process.terminate()
        for process in processes:
            try:
                process.wait(30)
            except subprocess.TimeoutExpired:
                process.kill()
        for log in logs:
            log.close()
