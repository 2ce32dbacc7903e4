"""View3D > Sidebar > Seamless AO: settings, Bake, Clear, preview and the last bake's numbers."""

import bpy

from ..core.rays.cycles_rules import NOT_FOR_CYCLES
from ..core.settings import PRESET_CHOOSES, QUALITY_ITEMS, item_label
from ..operators.adapters.scene_settings import automatic_caster_line
from ..operators.poll import stale_bakes
from .text import wrapped_labels

class SidebarPanel:
    """What every Seamless AO panel shares: where it lives, and a property-split column."""

    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Seamless AO"

    def settings_column(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        return layout.column(), context.scene.seamless_ao


class SubPanel(SidebarPanel):
    bl_parent_id = "VIEW3D_PT_seamless_ao"
    bl_options = {"DEFAULT_CLOSED"}
    #: Settings drawn one per row, in order.
    settings = ()

    def draw(self, context):
        column, settings = self.settings_column(context)
        for name in self.settings:
            self.setting_row(column, settings, name)

    @staticmethod
    def setting_row(column, settings, name):
        """One setting; greyed out (still editable: the bake then says why it refuses, or leaves it) where the
        chosen ray caster cannot follow it, or where the Quality preset chooses it."""
        row = column.row()
        row.active = not (settings.ray_caster == "CYCLES" and name in NOT_FOR_CYCLES or
                          settings.quality != "CUSTOM" and name in PRESET_CHOOSES)
        row.prop(settings, name)


class VIEW3D_PT_seamless_ao(SidebarPanel, bpy.types.Panel):
    bl_label = "Seamless AO"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.seamless_ao
        layout.prop(settings, "quality")
        column = layout.column(align=True)
        column.scale_y = 1.4
        column.operator("object.seamless_ao_bake", icon="RENDER_STILL")
        row = layout.row(align=True)
        row.operator("object.seamless_ao_clear", text="Clear", icon="TRASH")
        row.prop(settings, "preview", toggle=True, icon="HIDE_OFF")
        stale = stale_bakes(context)
        if stale:
            wrapped_labels(layout.box(), context, "AO not shown on {}: the modifiers give another surface than "
                           "the one baked. Bake again.".format(", ".join(ob.name for ob in stale)), icon="ERROR",
                           in_box=True)
        if settings.last_bake_summary:
            box = layout.box()
            box.label(text="Last bake", icon="INFO")
            for name, value in last_bake_rows(settings):
                row = box.row()
                row.label(text=name)
                row.label(text=value)


def last_bake_rows(settings):
    """``[(label, value)]`` of the Last bake box, each pair drawn on one row."""
    quality, _, image = settings.last_bake_quality.partition(", ")
    return [("Quality", quality), ("Image", image),
            ("Time", "{:.1f} s".format(settings.last_bake_time)),
            ("Texels", "{:,}".format(settings.last_bake_texels)),
            ("Rays", "{:,.0f}".format(settings.last_bake_rays)),
            ("Atlas use", "{:.0%}".format(settings.last_bake_utilisation)),
            ("Noise (raw, 1σ)", "≈ {:.3f}".format(settings.last_bake_noise))]


class VIEW3D_PT_seamless_ao_advanced(SubPanel, bpy.types.Panel):
    """Today's knobs, closed: the Quality preset chooses the rays and the image size unless it is Custom."""

    bl_label = "Advanced"

    def draw(self, context):
        settings = context.scene.seamless_ao
        if settings.quality != "CUSTOM":
            wrapped_labels(self.layout, context, "Quality {} chooses the rays and the image size; Custom leaves "
                           "them to you.".format(item_label(QUALITY_ITEMS, settings.quality)), icon="INFO")


class AdvancedPanel(SubPanel):
    bl_parent_id = "VIEW3D_PT_seamless_ao_advanced"


class VIEW3D_PT_seamless_ao_rays(AdvancedPanel, bpy.types.Panel):
    bl_label = "Rays"
    bl_options = set()

    def draw(self, context):
        column, settings = self.settings_column(context)
        self.setting_row(column, settings, "rays")
        column.prop(settings, "auto_distance")
        row = column.row()
        row.enabled = not settings.auto_distance
        row.prop(settings, "max_distance")
        for name in ("cone_angle", "falloff", "distribution", "adaptive", "weighted_rays", "denoise", "seed"):
            self.setting_row(column, settings, name)


class VIEW3D_PT_seamless_ao_occluders(AdvancedPanel, bpy.types.Panel):
    bl_label = "Occluders"
    settings = ("use_scene_occluders", "use_ground_plane", "ignore_backfaces", "horizon_bias", "ray_caster")

    def draw(self, context):
        SubPanel.draw(self, context)
        line = automatic_caster_line(context.scene.seamless_ao)
        if line:
            wrapped_labels(self.layout, context, line, icon="INFO")


class VIEW3D_PT_seamless_ao_image(AdvancedPanel, bpy.types.Panel):
    bl_label = "Charts and Image"

    def draw(self, context):
        column, settings = self.settings_column(context)
        self.setting_row(column, settings, "size_mode")
        self.setting_row(column, settings, "image_size" if settings.size_mode == "IMAGE_SIZE" else "texel_density")
        for name in ("padding", "compare_angle", "memory_budget_mb"):
            column.prop(settings, name)


class VIEW3D_PT_seamless_ao_output(SubPanel, bpy.types.Panel):
    bl_label = "Output"
    settings = ("hook_materials", "save_image")


class VIEW3D_PT_seamless_ao_export(SubPanel, bpy.types.Panel):
    bl_label = "Export"

    def draw(self, context):
        column, settings = self.settings_column(context)
        ob = context.active_object
        if ob is not None and ob.type == "MESH":
            column.prop_search(settings, "export_uv_map", ob.data, "uv_layers")
        else:
            column.prop(settings, "export_uv_map")
        for name in ("export_size", "export_padding", "export_gltf_occlusion", "export_material_strength",
                     "export_packing", "export_bit_depth", "export_unfit_uv_map"):
            column.prop(settings, name)
        column.operator("object.seamless_ao_resample", icon="UV")
        column.separator()
        column.prop(settings, "export_domain")
        column.operator("object.seamless_ao_to_color", icon="GROUP_VCOL")
