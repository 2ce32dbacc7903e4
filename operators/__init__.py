"""The Blender side: user intent in, core calls out, results into Blender data.

By role:

* ``adapters/``: read Blender data into core arrays and write results back (meshes, ray casters, the bake
  session, images, UV maps and materials as one transaction, exports, Clear);
* ``ui/``: what the user touches: the operators (one per file), their ``poll`` messages, the scene's
  property group, the ``seamless_ao`` command line;
* ``batch/``: folders of assets baked in worker processes;
* ``standalone/``: the same command line and the demo, run with the ``bpy`` module instead of Blender.
"""

import bpy

from .ui import command_line, properties
from .ui.bake_operator import OBJECT_OT_seamless_ao_bake
from .ui.clear_operator import OBJECT_OT_seamless_ao_clear
from .ui.color_attribute_operator import OBJECT_OT_seamless_ao_to_color
from .ui.resample_operator import OBJECT_OT_seamless_ao_resample

classes = (OBJECT_OT_seamless_ao_bake, OBJECT_OT_seamless_ao_clear, OBJECT_OT_seamless_ao_resample,
           OBJECT_OT_seamless_ao_to_color)

_register_classes, _unregister_classes = bpy.utils.register_classes_factory(classes)


def register():
    properties.register()
    _register_classes()
    command_line.register()


def unregister():
    command_line.unregister()
    _unregister_classes()
    properties.unregister()
