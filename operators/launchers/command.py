"""``blender --background [FILE.blend] --command seamless_ao ARGS`` with the ``bpy`` module instead of Blender.

    python operators/launchers/launch.py command FILE.blend bake --rays 32 --save
    python operators/launchers/launch.py command batch assets/ --output-dir baked/   (make batch)

With the add-on registered (by :mod:`.launch`, as Blender does at start-up),
opens the file (if the first argument is a .blend) and runs the ``seamless_ao`` command
(:mod:`.command_line`); returns its exit code.
"""

import bpy

from .command_line import run


def main(argv):
    argv = list(argv)
    if argv and argv[0].endswith(".blend"):
        bpy.ops.wm.open_mainfile(filepath=argv.pop(0))
    return run(argv)
