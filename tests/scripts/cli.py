"""Stand-in for ``blender --background FILE --command seamless_ao ARGS`` with the bpy module.

    python cli.py FILE.blend ARGS...

Opens the file, registers the add-on (as Blender would at start-up), and runs
the command the add-on registered with ``bpy.utils.register_cli_command``;
the exit code is the command's.
"""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "support"))

import bpy  # noqa: E402
import package  # noqa: E402


def main(blend, argv):
    bpy.ops.wm.open_mainfile(filepath=blend)
    package.seamless_ao.register()
    from seamless_ao.operators import cli
    return cli.run(argv)


if __name__ == "__main__":
    arguments = package.script_arguments()
    package.hard_exit(main(arguments[0], arguments[1:]))
