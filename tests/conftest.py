"""Fixtures shared by every test (``tests/core``: numpy and mathutils only; ``tests/blender``: Blender data).

The tests' own helper modules live in ``tests/support`` (meshes, scenes, the
plain reference, checks); ``support/package.py`` imports ``bpy`` and the add-on.
"""

import faulthandler
import os
import pathlib
import subprocess
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "support"))      # the tests' helper modules

import bpy  # noqa: E402
import pytest  # noqa: E402

import watchdog  # noqa: E402
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


#: Seconds one test may take before the session is taken for hung.  The slowest test takes about two
#: minutes on a busy 2-core machine; a hang (a native thread that never wakes, say) would otherwise sit
#: until CI's own limit ends the run with no word of where.  Past this, support/watchdog.py writes every
#: thread's native and Python stacks and the test's id to the terminal and ends the session.  The
#: environment variable SEAMLESS_AO_TEST_STALL sets another (tests/blender/test_session.py uses it).
TEST_STALL = float(os.environ.get("SEAMLESS_AO_TEST_STALL", 900))

_EXIT_STATUS = [0]
_WATCHDOG = []


def pytest_configure(config):
    # inside a real Blender (tests/run.py) the session is one test of an outer session, which has its watchdog
    if bpy.app.binary_path:
        return
    # a copy of the terminal's stderr, made while pytest's capture is suspended (a test's own stderr is
    # captured into a file), for the stacks faulthandler writes when the watchdog asks; kept open in _WATCHDOG
    terminal = os.fdopen(os.dup(sys.__stderr__.fileno()), "w")
    faulthandler.register(watchdog.STACK_SIGNAL, file=terminal, all_threads=True)
    process = subprocess.Popen([sys.executable, watchdog.__file__, str(os.getpid()), str(TEST_STALL)],
                               stdin=subprocess.PIPE, stdout=terminal, stderr=terminal)
    _WATCHDOG[:] = [process, terminal]


def _tell_watchdog(line):
    try:
        _WATCHDOG[0].stdin.write(line.encode("utf-8") + b"\n")
        _WATCHDOG[0].stdin.flush()
    except (OSError, IndexError):
        pass                                     # no watchdog: the tests run as before


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _tell_watchdog(item.nodeid)
    try:
        yield
    finally:
        _tell_watchdog("-")


def pytest_sessionfinish(session, exitstatus):
    _EXIT_STATUS[0] = int(exitstatus)


def pytest_unconfigure(config):
    if bpy.app.version < (4, 3, 0) and not bpy.app.binary_path:
        hard_exit(_EXIT_STATUS[0])         # see package.hard_exit: the bpy 4.2 module's teardown crashes
