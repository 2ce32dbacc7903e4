"""Open a .blend the way a user who trusts it would: ``python open_blend.py FILE.blend --allow-scripts``.

The batch test's control: with scripts allowed, a text block registered to run
on load does run (so a test that finds no trace of it after a batch can fail).
"""

import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "support"))

import bpy  # noqa: E402
import package  # noqa: E402

if __name__ == "__main__":
    arguments = package.script_arguments()
    bpy.ops.wm.open_mainfile(filepath=arguments[0], load_ui=False, use_scripts="--allow-scripts" in arguments)
    package.hard_exit(0)
