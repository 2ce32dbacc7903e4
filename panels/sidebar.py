"""View3D > Sidebar > Seamless AO: settings, Bake, Clear, preview and the last bake's numbers."""

import bpy


class VIEW3D_PT_seamless_ao(bpy.types.Panel):
    bl_label = "Seamless AO"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.seamless_ao
        column = layout.column(align=True)
        column.scale_y = 1.4
        column.operator("object.seamless_ao_bake", icon="RENDER_STILL")
        row = layout.row(align=True)
        row.operator("object.seamless_ao_clear", icon="TRASH")
        row.prop(settings, "preview", toggle=True, icon="HIDE_OFF")
        if settings.last_bake_summary:
            box = layout.box()
            box.label(text="Last bake", icon="INFO")
            grid = box.grid_flow(columns=2, even_columns=True)
            grid.label(text="Time")
            grid.label(text="{:.1f} s".format(settings.last_bake_time))
            grid.label(text="Texels")
            grid.label(text="{:,}".format(settings.last_bake_texels))
            grid.label(text="Rays")
            grid.label(text="{:,.0f}".format(settings.last_bake_rays))
            grid.label(text="Atlas use")
            grid.label(text="{:.0%}".format(settings.last_bake_utilisation))


class VIEW3D_PT_seamless_ao_rays(bpy.types.Panel):
    bl_label = "Rays"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"
    bl_parent_id = "VIEW3D_PT_seamless_ao"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.seamless_ao
        column = layout.column()
        column.prop(settings, "rays")
        column.prop(settings, "auto_distance")
        row = column.row()
        row.enabled = not settings.auto_distance
        row.prop(settings, "max_distance")
        column.prop(settings, "cone_angle")
        column.prop(settings, "falloff")
        column.prop(settings, "distribution")
        column.prop(settings, "adaptive")
        column.prop(settings, "denoise")
        column.prop(settings, "seed")


class VIEW3D_PT_seamless_ao_occluders(bpy.types.Panel):
    bl_label = "Occluders"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"
    bl_parent_id = "VIEW3D_PT_seamless_ao"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.seamless_ao
        column = layout.column()
        column.prop(settings, "use_scene_occluders")
        column.prop(settings, "use_ground_plane")
        column.prop(settings, "ignore_backfaces")
        column.prop(settings, "horizon_bias")
        column.prop(settings, "ray_caster")


class VIEW3D_PT_seamless_ao_image(bpy.types.Panel):
    bl_label = "Charts and Image"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"
    bl_parent_id = "VIEW3D_PT_seamless_ao"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.seamless_ao
        column = layout.column()
        column.prop(settings, "size_mode")
        if settings.size_mode == "IMAGE_SIZE":
            column.prop(settings, "image_size")
        else:
            column.prop(settings, "texel_density")
        column.prop(settings, "padding")
        column.prop(settings, "compare_angle")
        column.prop(settings, "memory_budget_mb")


class VIEW3D_PT_seamless_ao_output(bpy.types.Panel):
    bl_label = "Output"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"
    bl_parent_id = "VIEW3D_PT_seamless_ao"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.seamless_ao
        column = layout.column()
        column.prop(settings, "hook_materials")
        column.prop(settings, "save_image")


class VIEW3D_PT_seamless_ao_export(bpy.types.Panel):
    bl_label = "Export"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"
    bl_parent_id = "VIEW3D_PT_seamless_ao"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.seamless_ao
        column = layout.column()
        ob = context.active_object
        if ob is not None and ob.type == "MESH":
            column.prop_search(settings, "export_uv_map", ob.data, "uv_layers")
        else:
            column.prop(settings, "export_uv_map")
        column.prop(settings, "export_size")
        column.prop(settings, "export_padding")
        column.prop(settings, "export_gltf_occlusion")
        column.operator("object.seamless_ao_resample", icon="UV")
        column.separator()
        column.prop(settings, "export_domain")
        column.operator("object.seamless_ao_to_color", icon="GROUP_VCOL")
