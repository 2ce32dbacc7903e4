"""View3D > Sidebar > Seamless AO."""

import bpy


class VIEW3D_PT_seamless_ao(bpy.types.Panel):
    bl_label = "Seamless AO"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.seamless_ao
        layout.operator("object.seamless_ao_bake", icon="RENDER_STILL")
        col = layout.column(align=True)
        col.prop(settings, "rays")
        col.prop(settings, "image_size")
