"""Operators: user intent in, core calls out, results into Blender data."""

import bpy

from . import properties
from .bake import OBJECT_OT_seamless_ao_bake

classes = (OBJECT_OT_seamless_ao_bake,)

_register_classes, _unregister_classes = bpy.utils.register_classes_factory(classes)


def register():
    properties.register()
    _register_classes()


def unregister():
    _unregister_classes()
    properties.unregister()
