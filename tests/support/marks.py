"""Which tests run on which Blender.  ``docs/tested.md`` is written from these marks
(``tests/scripts/write_docs.py``), so it says exactly what each Blender runs."""

import bpy
import pytest

#: The Blender (major, minor) that runs the heavy tests: the default one, 5.0.  Heavy are the tests of a
#: minute or more, and the accuracy checks beyond the cases that take each of Blender's paths (a hard mesh,
#: one more modifier stack, a mirrored plane's seam): what they measure is the bake's own arithmetic,
#: which the other Blenders share, and their path through Blender a lighter test takes on every Blender.
HEAVY_BLENDER = (5, 0)

heavy = pytest.mark.skipif(bpy.app.version[:2] != HEAVY_BLENDER,
                           reason="heavy: run on Blender {}.{} only".format(*HEAVY_BLENDER))
