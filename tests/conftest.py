"""Test setup shared by every test.

The repository root *is* the add-on package.  It is imported here under the
name ``seamless_ao`` (Blender itself imports it as ``bl_ext.<repo>.seamless_ao``),
which the add-on allows because it uses relative imports only.  ``bpy`` comes
from the pinned PyPI wheel of the Blender version under test.
"""

import importlib.util
import os
import pathlib
import sys
import tempfile

# Keep Blender's user config (extensions, preferences) out of the user's home.
os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="seamless_ao_user_"))

import bpy  # noqa: E402  (must come after the environment is set)
import pytest  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
TESTS = ROOT / "tests"
if str(TESTS) not in sys.path:
    sys.path.insert(0, str(TESTS))


def load_package(name="seamless_ao"):
    """Import the repository root as package ``name`` (once)."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(
        name, ROOT / "__init__.py", submodule_search_locations=[str(ROOT)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


seamless_ao = load_package()


@pytest.fixture
def addon():
    """The add-on, registered for one test (registering takes milliseconds)."""
    seamless_ao.register()
    yield seamless_ao
    seamless_ao.unregister()


@pytest.fixture
def fresh_scene():
    """An empty factory-startup scene."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield bpy.context.scene


# The bpy 4.2 module crashes while the interpreter shuts down once any
# PropertyGroup has been registered (even after unregistering it); Blender
# itself is unaffected and later bpy wheels are fine.  Leave without the
# interpreter's teardown there, keeping pytest's exit status.
_EXIT_STATUS = [0]


def pytest_sessionfinish(session, exitstatus):
    _EXIT_STATUS[0] = int(exitstatus)


def pytest_unconfigure(config):
    if bpy.app.version < (4, 3, 0):
        hard_exit(_EXIT_STATUS[0])


def hard_exit(status):
    """``os._exit`` after flushing: skips the bpy 4.2 module's crashing teardown."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
