"""UI only: the 3D View sidebar panel and its sub-panels."""

import bpy

from .sidebar import (VIEW3D_PT_seamless_ao, VIEW3D_PT_seamless_ao_advanced, VIEW3D_PT_seamless_ao_export,
                      VIEW3D_PT_seamless_ao_image, VIEW3D_PT_seamless_ao_occluders, VIEW3D_PT_seamless_ao_output,
                      VIEW3D_PT_seamless_ao_rays)

classes = (
    VIEW3D_PT_seamless_ao,
    VIEW3D_PT_seamless_ao_advanced,
    VIEW3D_PT_seamless_ao_rays,
    VIEW3D_PT_seamless_ao_occluders,
    VIEW3D_PT_seamless_ao_image,
    VIEW3D_PT_seamless_ao_output,
    VIEW3D_PT_seamless_ao_export,
)

register, unregister = bpy.utils.register_classes_factory(classes)
