"""Fixtures shared by every test (``tests/core``: numpy and mathutils only; ``tests/blender``: Blender data).

The tests' own helper modules live in ``tests/support`` (meshes, scenes, the
plain reference, checks); ``support/package.py`` imports ``bpy`` and the add-on.
"""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "support"))      # the tests' helper modules

import bpy  # noqa: E402
import pytest  # noqa: E402

from package import hard_exit, seamless_ao  # noqa: E402


@pytest.fixture
def addon():
    """The add-on, registered for one test (registering takes milliseconds)."""
    seamless_ao.register()
    yield seamless_ao
    seamless_ao.unregister()


@pytest.fixture
def fresh_scene():
    """An empty factory-startup scene: the reset each Blender test starts from."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield bpy.context.scene


_EXIT_STATUS = [0]


def pytest_sessionfinish(session, exitstatus):
    _EXIT_STATUS[0] = int(exitstatus)


def pytest_unconfigure(config):
    if bpy.app.version < (4, 3, 0) and not bpy.app.binary_path:
        hard_exit(_EXIT_STATUS[0])         # see package.hard_exit: the bpy 4.2 module's teardown crashes
