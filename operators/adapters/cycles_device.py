"""Which device Cycles' part of a bake runs on: the one the user's Cycles preferences name (Preferences >
System > Cycles Render Devices), a GPU where one is set up, the CPU otherwise.

Processes of Seamless AO's own (the window's background bake, the batch's workers) start with factory
settings, so they would see no GPU preference: :func:`..processes.process_environment` hands them this
process's in :data:`DEVICE_VARIABLE`, and :func:`apply_from_environment` sets it up there.
"""

import json
import os

import bpy

#: The environment variable that carries the Cycles device preference to a process of ours (JSON).
DEVICE_VARIABLE = "SEAMLESS_AO_CYCLES_DEVICE"


def _cycles_preferences():
    addon = bpy.context.preferences.addons.get("cycles")
    return addon.preferences if addon is not None else None


def device_preference():
    """``{"type": compute device type, "use": [ids of the devices turned on]}`` from this Blender's Cycles
    preferences, or None where Cycles is not enabled or names no GPU type."""
    preferences = _cycles_preferences()
    if preferences is None or preferences.compute_device_type == "NONE":
        return None
    return {"type": preferences.compute_device_type,
            "use": [device.id for device in preferences.devices if device.use]}


def apply_device_preference(preference):
    """Set this Blender's Cycles preferences to ``preference`` (:func:`device_preference`'s; None: nothing)."""
    preferences = _cycles_preferences()
    if preference is None or preferences is None:
        return
    try:
        preferences.compute_device_type = preference["type"]
    except TypeError:                              # a type this Blender was not built with: the CPU it is
        return
    preferences.refresh_devices()
    for device in preferences.devices:
        device.use = device.id in preference["use"]


def apply_from_environment():
    """In a process of ours: take the preference the process that started it handed over, if any."""
    text = os.environ.get(DEVICE_VARIABLE)
    if text:
        apply_device_preference(json.loads(text))


def environment_entry():
    """``{DEVICE_VARIABLE: JSON}`` for a process of ours, or ``{}`` when there is no GPU preference."""
    preference = device_preference()
    return {DEVICE_VARIABLE: json.dumps(preference)} if preference is not None else {}


def cycles_device():
    """``(device, warning)``: ``"GPU"`` where the Cycles preferences name a GPU type and one of its devices
    is turned on and present, else ``"CPU"``, with a sentence for the user when a GPU was asked for but
    none is there (else None)."""
    preferences = _cycles_preferences()
    if preferences is None or preferences.compute_device_type == "NONE":
        return "CPU", None
    preferences.refresh_devices()                  # headless, the list is empty until refreshed
    if preferences.has_active_device():
        return "GPU", None
    kind = preferences.compute_device_type
    return "CPU", ("Cycles' preferences ask for {} but no such device is on: Cycles' part of the bake ran on the "
                   "CPU".format(kind))
