"""The test suite inside a real Blender (its own Python needs pytest):

    blender --background --factory-startup --python tests/run.py [-- PYTEST ARGS]

The tests then use Blender's own ``bpy``; scripts the tests start run in
Blender too (``bpy.app.binary_path``), and an installed, enabled Seamless AO
extension is tested as installed (see ``tests/support/package.py``).
"""

import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
sys.exit(pytest.main(["-c", str(ROOT / "pytest.ini"), "--rootdir", str(ROOT), str(ROOT / "tests"), *arguments]))
