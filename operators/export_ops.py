"""``object.seamless_ao_resample`` and ``object.seamless_ao_to_color``: get the AO out of Blender."""

import bpy
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty

from ..core.errors import SeamlessAOError
from . import api, export

DOMAINS = (("CORNER", "Face Corner", "One value per face corner (sharp where the AO is)"),
           ("POINT", "Vertex", "One value per vertex (the corners averaged)"))


class NeedsBake:
    """Poll shared by the export operators: a baked mesh must be selected."""

    @classmethod
    def poll(cls, context):
        missing = "Bake Seamless AO first: the selected meshes have no bake to export"
        return api.poll_explained(cls, api.baked_selection_problem(context, missing))


class OBJECT_OT_seamless_ao_resample(NeedsBake, bpy.types.Operator):
    """Write the blended AO into a new image on one of the object's own UV maps (for engines and glTF)"""

    bl_idname = "object.seamless_ao_resample"
    bl_label = "Resample AO to UV Map"
    bl_options = {"REGISTER", "UNDO"}

    uv_map: StringProperty(name="UV Map", description="Target UV map (empty: the render-active one)")
    size: IntProperty(name="Size", description="Width and height of the new image", default=1024, min=8,
                      max=16384)
    padding: IntProperty(name="Padding", description="Texels of dilation around every UV island", default=8,
                         min=0, max=64)
    gltf_occlusion: BoolProperty(name="glTF Occlusion", default=True,
                                 description="Wire the image into the materials as the glTF occlusion texture")

    def invoke(self, context, event):
        props = context.scene.seamless_ao
        for name in ("uv_map", "size", "padding", "gltf_occlusion"):
            if not self.properties.is_property_set(name):
                setattr(self, name, getattr(props, "export_" + name))
        return self.execute(context)

    def execute(self, context):
        try:
            names = export.resample([ob for ob in api.target_objects(context) if api.has_bake(ob)],
                                    self.uv_map or None, self.size, self.padding, self.gltf_occlusion)
        except SeamlessAOError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "Resampled AO into " + ", ".join(names))
        return {"FINISHED"}


class OBJECT_OT_seamless_ao_to_color(NeedsBake, bpy.types.Operator):
    """Write the blended AO into a colour attribute "AO" (real-time use without textures)"""

    bl_idname = "object.seamless_ao_to_color"
    bl_label = "AO to Colour Attribute"
    bl_options = {"REGISTER", "UNDO"}

    domain: EnumProperty(name="Domain", items=DOMAINS, default="CORNER")

    def invoke(self, context, event):
        if not self.properties.is_property_set("domain"):
            self.domain = context.scene.seamless_ao.export_domain
        return self.execute(context)

    def execute(self, context):
        try:
            export.to_color_attribute([ob for ob in api.target_objects(context) if api.has_bake(ob)], self.domain)
        except SeamlessAOError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "Wrote the AO into colour attribute '{}'".format(export.COLOR_ATTRIBUTE))
        return {"FINISHED"}
