"""The test suite inside a real Blender (its own Python needs pytest):

    blender --background --factory-startup --python tests/run.py [-- [TEST PATHS] [PYTEST ARGS]]

The tests then use Blender's own ``bpy``; scripts the tests start run in
Blender too (``bpy.app.binary_path``), and an installed, enabled Seamless AO
extension is tested as installed (see ``tests/support/package.py``).  Folders
listed in ``SEAMLESS_AO_PATHS`` are added to ``sys.path`` first, as the
product's launcher does (Blender ignores ``PYTHONPATH``): where a wheel such
as xatlas was unpacked for a Blender that has not installed the extension.
"""

import os
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
for entry in os.environ.get("SEAMLESS_AO_PATHS", "").split(os.pathsep):
    if entry and entry not in sys.path:
        sys.path.append(entry)
arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
paths = [] if any(os.path.exists(argument.split("::")[0]) for argument in arguments) else [str(ROOT / "tests")]
sys.exit(pytest.main(["-c", str(ROOT / "pytest.ini"), "--rootdir", str(ROOT), *paths, *arguments]))
