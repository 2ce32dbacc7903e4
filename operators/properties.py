"""Blender properties generated from :class:`core.settings.BakeSettings`.

One ``PropertyGroup`` on the scene (``scene.seamless_ao``) holds the settings
the panel shows; the bake operator has properties of the same names, and a
script that sets one of them overrides the scene's value for that call.
"""

import dataclasses

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from ..core.settings import BakeSettings, setting_fields


def blender_property(f):
    """A ``bpy.props`` definition for one :class:`BakeSettings` field."""
    meta = f.metadata
    common = dict(name=meta["label"], description=meta["description"], default=f.default)
    if "items" in meta:
        return EnumProperty(items=meta["items"], **common)
    if isinstance(f.default, bool):
        return BoolProperty(**common)
    limits = {key: meta[key] for key in ("min", "max") if key in meta}
    if isinstance(f.default, int):
        return IntProperty(**common, **limits)
    return FloatProperty(**common, **limits, precision=3 if meta.get("unit") != "°" else 1)


def setting_annotations():
    """``{name: property}`` for every bake setting."""
    return {f.name: blender_property(f) for f in setting_fields()}


def settings_from(source, overrides=None):
    """:class:`BakeSettings` read from a property holder (scene group or operator).

    ``overrides`` is an optional second holder whose explicitly set properties win.
    """
    values = {f.name: getattr(source, f.name) for f in setting_fields()}
    if overrides is not None:
        for f in setting_fields():
            if overrides.properties.is_property_set(f.name):
                values[f.name] = getattr(overrides, f.name)
    return BakeSettings.from_kwargs(**values)


def _preview_changed(self, context):
    from . import api
    scene = context.scene
    api.set_preview([ob for ob in scene.objects if api.has_bake(ob)], self.preview)


def _stats_annotations():
    return {
        "last_bake_summary": StringProperty(
            name="Last Bake", description="What the last bake did", default=""),
        "last_bake_time": FloatProperty(name="Time", description="Seconds the last bake took", default=0.0),
        "last_bake_texels": IntProperty(name="Texels", description="Texels the last bake computed", default=0),
        "last_bake_rays": FloatProperty(name="Rays", description="Rays the last bake cast", default=0.0),
        "last_bake_utilisation": FloatProperty(
            name="Atlas Use", description="Fraction of the image covered by charts", default=0.0),
        "last_bake_noise": FloatProperty(
            name="Noise", description="Expected noise of the last bake's AO before denoising (one standard "
            "deviation, for independent rays; stratified rays and the denoiser do better)", default=0.0),
        "export_uv_map": StringProperty(
            name="UV Map", description="UV map to resample the AO onto (empty: the render-active one)", default=""),
        "export_size": IntProperty(name="Size", description="Width and height of the resampled image",
                                   default=1024, min=8, max=16384),
        "export_padding": IntProperty(name="Padding", description="Texels of dilation around every UV island",
                                      default=8, min=0, max=64),
        "export_gltf_occlusion": BoolProperty(
            name="glTF Occlusion", default=True,
            description="Wire the resampled image into the materials as the glTF occlusion texture"),
        "export_domain": EnumProperty(
            name="Domain", default="CORNER",
            items=(("CORNER", "Face Corner", "One value per face corner"),
                   ("POINT", "Vertex", "One value per vertex (the corners averaged)"))),
        "preview": BoolProperty(
            name="Preview AO Only",
            description="Show only the baked AO on the baked objects' materials (emission), to judge it",
            default=False, update=_preview_changed),
    }


SeamlessAOSettings = type(
    "SeamlessAOSettings",
    (bpy.types.PropertyGroup,),
    {
        "__annotations__": {**setting_annotations(), **_stats_annotations()},
        "__doc__": "Seamless AO bake settings of this scene",
    },
)


def register():
    bpy.utils.register_class(SeamlessAOSettings)
    bpy.types.Scene.seamless_ao = PointerProperty(type=SeamlessAOSettings)


def unregister():
    del bpy.types.Scene.seamless_ao
    bpy.utils.unregister_class(SeamlessAOSettings)


def settings_dict(settings):
    """Plain ``dict`` of a :class:`BakeSettings`, for reports and logs."""
    return dataclasses.asdict(settings)
