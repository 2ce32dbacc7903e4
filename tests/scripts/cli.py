"""Stand-in for ``blender --background FILE --command seamless_ao ARGS`` with the bpy module.

    python cli.py FILE.blend ARGS...
    python cli.py batch ARGS...          (no file: the factory scene)

Opens the file, registers the add-on (as Blender would at start-up), and runs
the command the add-on registered with ``bpy.utils.register_cli_command``;
the exit code is the command's.
"""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "support"))

import bpy  # noqa: E402
import package  # noqa: E402


def main(argv):
    if argv and argv[0].endswith(".blend"):
        bpy.ops.wm.open_mainfile(filepath=argv.pop(0))
    package.seamless_ao.register()
    from seamless_ao.operators import cli
    return cli.run(argv)


if __name__ == "__main__":
    package.hard_exit(main(package.script_arguments()))
