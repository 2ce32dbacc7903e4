"""``object.seamless_ao_to_color``: the AO as a colour attribute (real-time use without textures)."""

import bpy

from ..core.keys import COLOR_ATTRIBUTE
from ..core.settings import COLOR_FIELDS
from .adapters.exports import to_color_attribute
from .export_operator_base import ExportOperator
from .poll import baked_targets


class OBJECT_OT_seamless_ao_to_color(ExportOperator, bpy.types.Operator):
    """Write the blended AO into a colour attribute "AO" (real-time use without textures)"""

    bl_idname = "object.seamless_ao_to_color"
    bl_label = "AO to Colour Attribute"
    fields = COLOR_FIELDS

    def export(self, context):
        to_color_attribute(baked_targets(context), self.domain, self.material_strength)
        return "Wrote the AO into colour attribute '{}'".format(COLOR_ATTRIBUTE)
