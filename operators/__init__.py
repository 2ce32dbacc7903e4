"""Operators: user intent in, core calls out, results into Blender data."""

import bpy

from . import cli, properties
from .bake import OBJECT_OT_seamless_ao_bake
from .clear import OBJECT_OT_seamless_ao_clear
from .resample import OBJECT_OT_seamless_ao_resample
from .to_color import OBJECT_OT_seamless_ao_to_color

classes = (OBJECT_OT_seamless_ao_bake, OBJECT_OT_seamless_ao_clear, OBJECT_OT_seamless_ao_resample,
           OBJECT_OT_seamless_ao_to_color)

_register_classes, _unregister_classes = bpy.utils.register_classes_factory(classes)


def register():
    properties.register()
    _register_classes()
    cli.register()


def unregister():
    cli.unregister()
    _unregister_classes()
    properties.unregister()
