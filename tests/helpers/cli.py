"""Stand-in for ``blender --background FILE --command seamless_ao ARGS`` with the bpy module.

    python cli.py FILE.blend ARGS...

Opens the file, registers the add-on (as Blender would at start-up), and runs
the command the add-on registered with ``bpy.utils.register_cli_command``;
the exit code is the command's.
"""

import os
import sys
import tempfile

os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="seamless_ao_cli_"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import bpy  # noqa: E402
import conftest  # noqa: E402


def main(blend, argv):
    bpy.ops.wm.open_mainfile(filepath=blend)
    package = conftest.seamless_ao
    package.register()
    from seamless_ao.operators import cli
    return cli.run(argv)


if __name__ == "__main__":
    conftest.hard_exit(main(sys.argv[1], sys.argv[2:]))
