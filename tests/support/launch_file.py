"""The product's own launcher (operators/launchers/launch.py), loaded by path: it is not in a package.

Scripts that start a Blender process of their own (tests/scripts) use it as the test session does
(:mod:`package`), without loading the add-on: to remove Blender's session folder before ``os._exit``.
"""

import importlib.util
import pathlib
import sys

#: The product's own launcher: the ``seamless_ao`` command line, the demo and batch workers without Blender.
LAUNCHER = pathlib.Path(__file__).resolve().parents[2] / "operators" / "launchers" / "launch.py"


def launcher():
    """operators/launchers/launch.py as the module ``seamless_ao_launch`` (loaded once)."""
    if "seamless_ao_launch" not in sys.modules:
        spec = importlib.util.spec_from_file_location("seamless_ao_launch", LAUNCHER)
        sys.modules["seamless_ao_launch"] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules["seamless_ao_launch"])
    return sys.modules["seamless_ao_launch"]
