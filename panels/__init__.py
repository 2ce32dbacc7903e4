"""UI only: the 3D View sidebar panel."""

import bpy

from .sidebar import VIEW3D_PT_seamless_ao

classes = (VIEW3D_PT_seamless_ao,)

register, unregister = bpy.utils.register_classes_factory(classes)
