"""Blender properties generated from :mod:`core.settings` (bake and export settings).

One ``PropertyGroup`` on the scene (``scene.seamless_ao``) holds the settings
the panel shows (export ones prefixed ``export_``); the operators have
properties of the same names, and a script that sets one of them overrides the
scene's value for that call.
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from ..core.settings import export_fields, setting_fields
from .adapters.preview import set_preview
from .poll import has_bake


def blender_property(f):
    """A ``bpy.props`` definition for one settings field (of :class:`BakeSettings` or ``ExportSettings``)."""
    meta = f.metadata
    common = dict(name=meta["label"], description=meta["description"], default=f.default)
    if "items" in meta:
        return EnumProperty(items=meta["items"], **common)
    if isinstance(f.default, bool):
        return BoolProperty(**common)
    if isinstance(f.default, str):
        return StringProperty(**common)
    limits = {key: meta[key] for key in ("min", "max") if key in meta}
    if isinstance(f.default, int):
        return IntProperty(**common, **limits)
    return FloatProperty(**common, **limits, precision=3 if meta.get("unit") != "°" else 1)


def setting_annotations():
    """``{name: property}`` for every bake setting."""
    return {f.name: blender_property(f) for f in setting_fields()}


def export_annotations(names=None, prefix=""):
    """``{prefix + name: property}`` for the export settings (those in ``names``, if given)."""
    return {prefix + f.name: blender_property(f) for f in export_fields(names)}


def fill_from_scene(operator, props, names, prefix="export_"):
    """Give each of the operator's properties ``names`` that the caller did not set the scene's value."""
    for name in names:
        if not operator.properties.is_property_set(name):
            setattr(operator, name, getattr(props, prefix + name))


def _preview_changed(self, context):
    set_preview([ob for ob in context.scene.objects if has_bake(ob)], self.preview)


def _stats_annotations():
    return {
        "last_bake_summary": StringProperty(
            name="Last Bake", description="What the last bake did", default=""),
        "last_bake_time": FloatProperty(name="Time", description="Seconds the last bake took", default=0.0),
        "last_bake_stages": StringProperty(
            name="Stages", description="Seconds of each stage of the last bake, as JSON (for scripts)", default=""),
        "last_bake_texels": IntProperty(name="Texels", description="Texels the last bake computed", default=0),
        "last_bake_rays": FloatProperty(name="Rays", description="Rays the last bake cast", default=0.0),
        "last_bake_utilisation": FloatProperty(
            name="Atlas Use", description="Fraction of the image covered by charts", default=0.0),
        "last_bake_noise": FloatProperty(
            name="Noise", description="Ray noise of the last bake's AO before denoising, estimated as if its rays "
            "were independent (one standard deviation, over the texels that got all their rays): an estimate, "
            "not a bound; stratified rays and the denoiser do better", default=0.0),
        "last_bake_quality": StringProperty(
            name="Quality", description="The last bake's Quality and the image size and rays it baked with",
            default=""),
        "preview": BoolProperty(
            name="Preview AO Only",
            description="Show only the baked AO on the baked objects' materials (emission), to judge it",
            default=False, update=_preview_changed),
    }


SeamlessAOSettings = type(
    "SeamlessAOSettings",
    (bpy.types.PropertyGroup,),
    {
        "__annotations__": {**setting_annotations(), **export_annotations(prefix="export_"), **_stats_annotations()},
        "__doc__": "Seamless AO bake settings of this scene",
    },
)


def register():
    bpy.utils.register_class(SeamlessAOSettings)
    bpy.types.Scene.seamless_ao = PointerProperty(type=SeamlessAOSettings)


def unregister():
    del bpy.types.Scene.seamless_ao
    bpy.utils.unregister_class(SeamlessAOSettings)
