"""The window's half of a background bake: hand the meshes to a process of ours, watch it, take the outcome.

    bake = BackgroundBake(meshes, matrices, occluders, settings)    # writes the job, starts the process
    while (state := bake.poll()) is not None:                       # (fraction, message); cheap, never blocks
        ...
    outcome = bake.outcome()                                        # core.other_processes.handoff.HandedBack
    bake.close()                                                    # ends the process, removes the folder

The process is :mod:`.bake_worker` in a background Blender (:mod:`..adapters.processes`), so the pipeline's
long calls (the atlas packer, Cycles' bakes) never freeze the window; Esc ends it at once.
"""

import os
import shutil
import subprocess
import tempfile

from ...core.errors import SeamlessAOError
from ...core.other_processes.handoff import outcome_written, read_failure, read_outcome, read_progress, write_job
from ..adapters.processes import process_command, process_environment

#: The lines of the process's log printed to the console when it fails through a fault of ours.
LOG_LINES = 30
#: How much less the process's share of the processor is than the window's (``nice`` steps): on a machine
#: whose cores the bake fills, the window's redraws still come first.
NICENESS = 10


def lower_priority(command):
    """``(command, Popen keywords)`` that start it at a lower priority than this process, where the system
    says how: ``nice`` on Linux and macOS, a below-normal priority class on Windows."""
    if os.name == "nt":
        return command, {"creationflags": subprocess.BELOW_NORMAL_PRIORITY_CLASS}
    nice = shutil.which("nice")
    return ([nice, "-n", str(NICENESS), *command] if nice else command), {}


class BackgroundBake:
    """One bake running in a process of its own; see the module's docstring."""

    def __init__(self, meshes, matrices, occluders, settings, shown=None):
        self.folder = tempfile.mkdtemp(prefix="seamless_ao_bake_")
        self.process = None
        try:
            write_job(self.folder, meshes, matrices, occluders, settings, shown)
            self.log_path = os.path.join(self.folder, "log.txt")
            command, keywords = lower_priority(process_command("bake-worker", self.folder))
            with open(self.log_path, "w", encoding="utf-8") as log:
                self.process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT,
                                                stdin=subprocess.DEVNULL, env=process_environment(self.folder),
                                                **keywords)
        except BaseException:
            self.close()
            raise

    def poll(self):
        """``(fraction, message)`` while the process bakes, None once its outcome is written; raises
        :class:`SeamlessAOError` with the process's sentence if it failed."""
        code = self.process.poll()
        if code is None:
            return read_progress(self.folder) or (0.02, "Starting the bake process")
        if code == 0 and outcome_written(self.folder):
            return None
        failure = read_failure(self.folder)
        if failure is not None and failure[1]:
            raise SeamlessAOError(failure[0])
        print("Seamless AO: the bake process failed; the end of its log:")
        with open(self.log_path, encoding="utf-8", errors="replace") as log:
            print("".join(log.readlines()[-LOG_LINES:]))
        raise RuntimeError(failure[0] if failure else "the bake process stopped with exit code {}".format(code))

    def outcome(self):
        """The :class:`~...core.other_processes.handoff.HandedBack` outcome (after :meth:`poll` returned None)."""
        return read_outcome(self.folder)

    def close(self):
        """End the process if it still runs and remove its folder (safe to call twice)."""
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        shutil.rmtree(self.folder, ignore_errors=True)
