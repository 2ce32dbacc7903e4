"""Run Seamless AO in a process of its own, from this folder, with no install.

    python operators/launchers/launch.py command [FILE.blend] ARGS...   # = blender -b [FILE] --command seamless_ao ARGS
    python operators/launchers/launch.py demo [--output-dir out] ...    # make demo
    python operators/launchers/launch.py worker JOB.json                # one batch worker (operators/batch/)
    python operators/launchers/launch.py bake-worker FOLDER             # a window's bake (operators/background/)
    blender --background --factory-startup --python operators/launchers/launch.py -- worker JOB.json

``python`` is one with the ``bpy`` module (the virtualenvs of ``make``), or
Blender itself runs this file.  It loads the package from the repository (or
extension) folder under a name of its own, so an installed copy is never
registered twice, and hands the rest of the command line to
:mod:`.command`, :mod:`.demo` or the batch worker.  Folders listed in the
environment variable ``SEAMLESS_AO_PATHS`` are added to ``sys.path`` first
(a batch passes its own, where Blender's extension wheels live), and the
Cycles device preference of the process that started this one is taken
(:mod:`..adapters.cycles_device`).

The process ends with ``os._exit``: the bpy 4.2 *module* crashes in
interpreter teardown once a PropertyGroup was registered.  Blender's own
session folder, which its teardown would remove, is removed first.
"""

import importlib
import importlib.util
import os
import pathlib
import shutil
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
NAME = "seamless_ao_standalone"
ENTRY_POINTS = {"command": "operators.launchers.command", "demo": "operators.launchers.demo",
                "worker": "operators.batch.worker", "bake-worker": "operators.background.bake_worker"}
#: The entry points that run with the add-on registered, as Blender registers it at start-up (before a file).
REGISTERED = {"command", "demo"}


def load_package(name=NAME):
    """The package in :data:`ROOT`, imported as ``name``."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, ROOT / "__init__.py", submodule_search_locations=[str(ROOT)])
    package = importlib.util.module_from_spec(spec)
    sys.modules[name] = package
    spec.loader.exec_module(package)
    return package


def arguments():
    """The launcher's own arguments: after ``--`` under Blender, after the script's name under Python."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]


def main(argv):
    if not argv or argv[0] not in ENTRY_POINTS:
        print("usage: launch.py {{{}}} ARGS...".format(",".join(ENTRY_POINTS)), file=sys.stderr)
        return 2
    for entry in os.environ.get("SEAMLESS_AO_PATHS", "").split(os.pathsep):
        if entry and entry not in sys.path:
            sys.path.append(entry)
    package = load_package()
    importlib.import_module(NAME + ".operators.adapters.cycles_device").apply_from_environment()
    if argv[0] in REGISTERED:
        package.register()
    return importlib.import_module(NAME + "." + ENTRY_POINTS[argv[0]]).main(argv[1:])


def remove_session_folder():
    """Remove Blender's session folder (``bpy.app.tempdir``, a ``blender_*`` folder in the temporary folder):
    Blender removes it when it shuts down itself, which ``os._exit`` skips, so every bake of a window or a
    batch would leave one behind.  Never the base folder, where Blender falls back to it."""
    bpy = sys.modules.get("bpy")
    session = bpy.app.tempdir.rstrip("/\\") if bpy is not None else ""
    if os.path.basename(session).startswith("blender_"):
        shutil.rmtree(session, ignore_errors=True)


if __name__ == "__main__":
    status = main(arguments())
    sys.stdout.flush()
    sys.stderr.flush()
    remove_session_folder()
    os._exit(status)
