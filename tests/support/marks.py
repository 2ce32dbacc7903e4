"""Which tests run on which Blender.  ``docs/tested.md`` is written from these marks
(``tests/scripts/write_docs.py``), so it says exactly what each Blender runs."""

import bpy
import pytest

#: The Blender (major, minor) that runs the heavy tests (a minute or more each): the default one, 5.0.
HEAVY_BLENDER = (5, 0)

heavy = pytest.mark.skipif(bpy.app.version[:2] != HEAVY_BLENDER,
                           reason="heavy: run on Blender {}.{} only".format(*HEAVY_BLENDER))
