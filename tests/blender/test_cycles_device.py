"""Issue 52: the Cycles caster bakes on the device the user's Cycles preferences name (a GPU where one is set
up, the CPU otherwise), falls back to the CPU with a warning, and hands the preference to the processes
it starts, which begin with factory settings (operators/adapters/cycles_device.py)."""

import json

import bpy
import numpy as np
import pytest

from seamless_ao.core.errors import SeamlessAOError
from seamless_ao.core.rays.ray_setup import AOParams
from seamless_ao.operators.adapters import cycles_caster, cycles_device
from seamless_ao.operators.adapters.casters import CyclesCaster
from seamless_ao.operators.adapters.processes import process_environment

CEILING = (np.array([[-60.0, -60.0, 1.0], [60.0, -60.0, 1.0], [60.0, 60.0, 1.0], [-60.0, 60.0, 1.0]]),
           np.array([[0, 2, 1], [0, 3, 2]]))
#: A GPU type every Linux build of Cycles knows; this machine has no such device.
GPU_TYPE = "CUDA"


def cycles_preferences():
    """Cycles' preferences as they are now (a factory reset makes them anew: never keep them)."""
    return bpy.context.preferences.addons["cycles"].preferences


@pytest.fixture
def preferences(fresh_scene):
    """Cycles' preferences after a factory reset, put back as they were after the test."""
    before = cycles_preferences().compute_device_type
    yield cycles_preferences()
    cycles_preferences().compute_device_type = before


def under_the_ceiling(caster, count=40):
    points = np.column_stack([np.linspace(-1.0, 1.0, count), np.zeros(count), np.zeros(count)])
    up = np.tile([0.0, 0.0, 1.0], (count, 1))
    return caster.ambient_occlusion(points, up, up, 64, AOParams(rays=64, max_distance=2.0, offset=1e-4))


def test_no_gpu_preference_bakes_on_the_cpu_and_says_nothing(preferences):
    preferences.compute_device_type = "NONE"
    assert cycles_device.cycles_device() == ("CPU", None)
    caster = CyclesCaster(*CEILING)
    try:
        open_fraction = under_the_ceiling(caster)
        assert caster.scene.cycles.device == "CPU" and caster.warnings == []
    finally:
        caster.free()
    assert np.isfinite(open_fraction).all()


def test_a_gpu_preference_with_no_gpu_bakes_on_the_cpu_with_a_warning(preferences):
    preferences.compute_device_type = GPU_TYPE
    device, warning = cycles_device.cycles_device()
    assert device == "CPU" and GPU_TYPE in warning and "CPU" in warning
    caster = CyclesCaster(*CEILING)
    try:
        under_the_ceiling(caster)
        assert caster.scene.cycles.device == "CPU" and caster.warnings == [warning]
    finally:
        caster.free()


def test_the_warning_reaches_the_bake_report(addon, preferences):
    preferences.compute_device_type = GPU_TYPE
    bpy.ops.mesh.primitive_monkey_add()
    report = __import__("package").seamless_ao.bake([bpy.context.active_object], rays=16, image_size=256,
                                                    ray_caster="CYCLES")
    assert any(GPU_TYPE in line and "CPU" in line for line in report.warnings), report.warnings


def test_a_failed_gpu_bake_is_baked_again_on_the_cpu_with_a_warning(preferences, monkeypatch):
    """The GPU is there but its bake fails (out of its memory, say): the CPU bakes the same texels."""
    monkeypatch.setattr(cycles_caster, "cycles_device", lambda: ("GPU", None))
    real_bake = cycles_caster.CyclesAmbientOcclusion._bake
    devices = []

    def bake(self, *arguments):
        devices.append(self.device)
        if self.device == "GPU":
            raise SeamlessAOError("Cycles could not bake the AO: out of GPU memory")
        return real_bake(self, *arguments)

    monkeypatch.setattr(cycles_caster.CyclesAmbientOcclusion, "_bake", bake)
    caster = CyclesCaster(*CEILING)
    try:
        open_fraction = under_the_ceiling(caster)
        assert devices == ["GPU", "CPU"] and caster.scene.cycles.device == "CPU"
        assert len(caster.warnings) == 1 and "out of GPU memory" in caster.warnings[0]
    finally:
        caster.free()
    # under a ceiling at height 1 within reach 2, the open fraction is 1 / 2² (test_cycles_caster.py)
    assert abs(open_fraction.mean() - 0.25) < 0.05


def test_processes_of_ours_get_the_preference_and_take_it(preferences, tmp_path):
    preferences.compute_device_type = "NONE"
    assert cycles_device.DEVICE_VARIABLE not in process_environment(str(tmp_path))
    preferences.compute_device_type = GPU_TYPE
    handed = json.loads(process_environment(str(tmp_path))[cycles_device.DEVICE_VARIABLE])
    assert handed["type"] == GPU_TYPE
    preferences.compute_device_type = "NONE"
    cycles_device.apply_device_preference(handed)               # what the process does at its start
    assert preferences.compute_device_type == GPU_TYPE
