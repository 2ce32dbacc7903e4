"""Processes of Seamless AO's own: a background Blender (or, under the ``bpy`` module, the same Python) that
runs this package from its folder, for the batch's workers and for the window's background bake.

    subprocess.Popen(process_command("worker", job_path), env=process_environment(scratch), ...)
"""

import os
import pathlib
import sys

import bpy

from ..batch.asset_process import launch_command, user_folders_moved
from .cycles_device import environment_entry

PACKAGE_ROOT = pathlib.Path(__file__).resolve().parents[2]
#: What such a process runs: this package loaded from its folder under a name of its own (so an installed
#: copy is never registered twice), then the entry point named first in its arguments.
LAUNCHER = PACKAGE_ROOT / "operators" / "launchers" / "launch.py"


def process_command(*arguments):
    """The command line that runs :mod:`..launchers.launch` with ``arguments``: background Blender with
    factory settings and no auto-run scripts, or this Python when ``bpy`` is the module."""
    binary = bpy.app.binary_path
    return launch_command(binary if binary and not os.path.basename(binary).startswith("python") else sys.executable,
                          LAUNCHER, *arguments)


def process_environment(scratch):
    """The process's environment: this process's, with Blender's user folders moved to ``scratch`` and this
    process's ``sys.path`` folders (where Blender keeps the extension's wheels) in ``SEAMLESS_AO_PATHS``, which
    :mod:`..launchers.launch` adds to the process's.

    The process has factory settings, in which no extension is enabled; were the user's extension folder its
    own, Blender's wheel upkeep (run by any factory reset) would delete the wheels of every extension it
    sees disabled there, this one's among them, from under the user's Blender and the other processes.  For
    the same reason it would see no GPU in Cycles' preferences: this process's go with it
    (:mod:`.cycles_device`)."""
    paths = [p for p in sys.path if p and os.path.isdir(p)]
    return dict(user_folders_moved(os.environ, scratch), SEAMLESS_AO_PATHS=os.pathsep.join(paths),
                **environment_entry())
