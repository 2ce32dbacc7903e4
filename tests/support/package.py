"""The add-on under test: the repository root imported as the package ``seamless_ao``.

Blender itself imports the package as ``bl_ext.<repository>.seamless_ao``; it
uses relative imports only, so the tests may import it under another name.
``bpy`` is the pinned PyPI wheel of the Blender version under test, or, when
the suite runs inside Blender (``blender -b --python tests/run.py``), Blender's
own, and an installed and enabled Seamless AO extension is used as it is
rather than loaded a second time.

Importing this module first points Blender's user resources at a temporary
folder, so no test or script touches the user's preferences or extensions.
"""

import atexit
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

#: This process's user resources folder, made here unless a parent process made one (the processes a test
#: starts inherit the variable and use the parent's); removed when this process ends.
OWN_USER_RESOURCES = None
if "BLENDER_USER_RESOURCES" not in os.environ:
    OWN_USER_RESOURCES = tempfile.mkdtemp(prefix="seamless_ao_user_")
    os.environ["BLENDER_USER_RESOURCES"] = OWN_USER_RESOURCES
    atexit.register(shutil.rmtree, OWN_USER_RESOURCES, ignore_errors=True)

import bpy  # noqa: E402  (must come after the environment is set)

from launch_file import LAUNCHER, launcher  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "tests" / "scripts"
NAME = "seamless_ao"


def load_package(name=NAME):
    """The package as ``name``: the installed extension if Blender has it enabled, else the repository root."""
    if name in sys.modules:
        return sys.modules[name]
    installed = next((n for n in sorted(sys.modules) if n.startswith("bl_ext.") and n.endswith("." + NAME)), None)
    if installed is not None:
        for module_name in [n for n in sys.modules if n == installed or n.startswith(installed + ".")]:
            sys.modules[name + module_name[len(installed):]] = sys.modules[module_name]
        return sys.modules[name]
    return launcher().load_package(name)


seamless_ao = load_package()


def run_command(*args, timeout=600):
    """``blender --background [FILE.blend] --command seamless_ao ARGS`` through the product's launcher."""
    return run_script(LAUNCHER, "command", *args, timeout=timeout)


def run_script(name, *args, timeout=600):
    """Run ``tests/scripts/<name>`` (or the script at a path) in a process of its own: the Python of the bpy
    module, or Blender itself in the background when the suite runs inside Blender (``bpy.app.binary_path``)."""
    script = str(SCRIPTS / name)
    if bpy.app.binary_path and not bpy.app.binary_path.endswith(("python", "python3")):
        command = [bpy.app.binary_path, "--background", "--factory-startup", "--python", script, "--", *args]
    else:
        command = [sys.executable, script, *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=timeout)


def script_arguments():
    """A script's own arguments: after ``--`` under Blender, after the script's name under Python."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]


def remove_temporary_folders():
    """Remove what this process leaves in the temporary folder: its user resources folder, if it made
    it, and Blender's session folder (``bpy.app.tempdir``, ``blender_*``), which Blender removes only
    when it shuts down itself (:func:`hard_exit` skips that)."""
    launcher().remove_session_folder()
    if OWN_USER_RESOURCES is not None:
        shutil.rmtree(OWN_USER_RESOURCES, ignore_errors=True)


def hard_exit(status):
    """``os._exit`` after flushing and :func:`remove_temporary_folders`.  The bpy 4.2 module crashes while
    the interpreter shuts down once any PropertyGroup was registered (later wheels and Blender itself are
    fine): scripts and the test session leave without that teardown."""
    sys.stdout.flush()
    sys.stderr.flush()
    remove_temporary_folders()
    os._exit(status)
