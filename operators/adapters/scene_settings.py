"""The scene's saved Seamless AO settings (``scene.seamless_ao``, or an operator's properties) read into
the core's :class:`~...core.settings.BakeSettings` and ``ExportSettings``."""

from ...core.errors import SeamlessAOError
from ...core.settings import (CASTER_ITEMS, BakeSettings, ExportSettings, export_fields, implied_quality, item_label,
                              setting_fields)
from .cycles_caster import cycles_enabled


def settings_from(source, overrides=None):
    """:class:`BakeSettings` read from a property holder (scene group or operator).

    ``overrides`` is an optional second holder whose explicitly set properties win (setting the rays or the
    image size there without a Quality means Custom: :func:`~...core.settings.implied_quality`).
    """
    values = {f.name: getattr(source, f.name) for f in setting_fields()}
    if overrides is not None:
        values.update(implied_quality({f.name: getattr(overrides, f.name) for f in setting_fields()
                                       if overrides.properties.is_property_set(f.name)}))
    return BakeSettings.from_kwargs(**values)


def automatic_caster_line(source):
    """What Ray Caster Automatic will cast with, as the panel says it under the setting ("Automatic: Cycles,
    all but ..."); None when a caster is chosen, or while the settings are invalid (the bake says why)."""
    if source.ray_caster != "AUTOMATIC":
        return None
    try:
        caster, why = settings_from(source).caster_choice(cycles_enabled())
    except SeamlessAOError:
        return None
    label = item_label(CASTER_ITEMS, caster)
    return "Automatic: {}, {}".format(label, why)


def scene_export_settings(scene):
    """:class:`ExportSettings` saved on the scene (the defaults if the add-on's properties are not there)."""
    props = getattr(scene, "seamless_ao", None)
    if props is None:
        return ExportSettings()
    return ExportSettings.from_kwargs(**{f.name: getattr(props, "export_" + f.name) for f in export_fields()})
