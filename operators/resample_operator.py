"""``object.seamless_ao_resample``: the AO as a texture on the object's own UV map (glTF-ready)."""

import bpy

from ..core.settings import RESAMPLE_FIELDS
from .adapters.exports import resample
from .export_operator_base import ExportOperator
from .poll import baked_targets


class OBJECT_OT_seamless_ao_resample(ExportOperator, bpy.types.Operator):
    """Write the blended AO into a new image on one of the object's own UV maps (for engines and glTF)"""

    bl_idname = "object.seamless_ao_resample"
    bl_label = "Resample AO to UV Map"
    fields = RESAMPLE_FIELDS

    def export(self, context):
        names = resample(baked_targets(context), **{name: getattr(self, name) for name in RESAMPLE_FIELDS})
        return "Resampled AO into " + ", ".join(names)
