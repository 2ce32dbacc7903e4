"""The Blender side: user intent in, core calls out, results into Blender data.

By role:

* here: the operators (one per file), their ``poll`` messages (:mod:`.poll`) and the scene's property
  group with the operators' properties made from core's settings (:mod:`.properties`);
* ``adapters/``: read Blender data into core arrays and write results back (meshes, ray casters, the bake
  session, images, UV maps and materials as one transaction, exports, Clear);
* ``background/``: a bake handed to a background Blender process, and that process;
* ``batch/``: folders of assets baked in worker processes, or on a Dask cluster;
* ``launchers/``: the ``seamless_ao`` command line, and the entry that runs it, the demo or a batch worker
  with the ``bpy`` module or a background Blender.
"""

import bpy

from . import properties
from .bake_operator import OBJECT_OT_seamless_ao_bake
from .clear_operator import OBJECT_OT_seamless_ao_clear
from .color_attribute_operator import OBJECT_OT_seamless_ao_to_color
from .launchers import command_line
from .resample_operator import OBJECT_OT_seamless_ao_resample

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
