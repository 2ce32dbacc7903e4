"""Which ray caster a bake's settings take, and what the Ray Caster items say about it (core/settings.py)."""

import pytest

from seamless_ao.core.errors import SeamlessAOError
from seamless_ao.core.rays.cycles_rules import BULK_PILOT_RAYS, CYCLES_NEEDS
from seamless_ao.core.settings import CASTER_ITEMS, BakeSettings


@pytest.mark.parametrize("name, value", [("falloff", "LINEAR"), ("cone_angle", 60.0), ("distribution", "UNIFORM"),
                                         ("ignore_backfaces", True), ("horizon_bias", 5.0),
                                         ("use_ground_plane", True)])
def test_the_cycles_caster_refuses_by_name_what_cycles_ao_cannot_do(name, value):
    assert BakeSettings.from_kwargs(ray_caster="CYCLES").ray_caster == "CYCLES"
    BakeSettings.from_kwargs(**{name: value})                          # fine with the Geometry Nodes caster
    with pytest.raises(SeamlessAOError, match="The Cycles ray caster cannot bake with {} = ".format(name)):
        BakeSettings.from_kwargs(ray_caster="CYCLES", **{name: value})
    # Automatic never refuses: it takes the Geometry Nodes caster instead
    assert BakeSettings.from_kwargs(ray_caster="AUTOMATIC", **{name: value}).caster_name() == "GEOMETRY_NODES"


def test_the_automatic_caster_is_cycles_for_classic_ao_with_rays_beyond_the_pilot():
    assert BakeSettings.from_kwargs(ray_caster="AUTOMATIC").caster_name() == "CYCLES"
    assert BakeSettings.from_kwargs(ray_caster="AUTOMATIC", rays=BULK_PILOT_RAYS + 1).caster_name() == "CYCLES"
    assert BakeSettings.from_kwargs(ray_caster="AUTOMATIC", rays=BULK_PILOT_RAYS).caster_name() == "GEOMETRY_NODES"
    for chosen in ("GEOMETRY_NODES", "PYTHON_BVH", "CYCLES"):
        assert BakeSettings.from_kwargs(ray_caster=chosen, rays=1).caster_name() == chosen



def test_the_automatic_caster_never_takes_cycles_where_cycles_is_not_enabled():
    """A user may turn Cycles off in the Preferences: Automatic then takes the node and says why; a chosen
    caster stays chosen (the Cycles caster then says it needs Cycles)."""
    assert BakeSettings.from_kwargs(ray_caster="AUTOMATIC").caster_choice(cycles_enabled=False) == (
        "GEOMETRY_NODES", "Cycles is not enabled in this Blender")
    assert BakeSettings.from_kwargs(ray_caster="CYCLES").caster_name(cycles_enabled=False) == "CYCLES"

def test_the_cycles_and_automatic_items_name_every_setting_cycles_needs():
    """Their descriptions read off CYCLES_NEEDS: a setting added there shows in both (the Cycles item once
    left out horizon bias)."""
    descriptions = {identifier: description for identifier, _, description in CASTER_ITEMS}
    assert len(CYCLES_NEEDS) == 6
    for _, _, _, in_short in CYCLES_NEEDS:
        assert in_short in descriptions["CYCLES"] and in_short in descriptions["AUTOMATIC"], in_short


def test_a_caster_declares_what_it_can_do_and_goes_by_its_settings_name():
    """core/rays/ray_setup.py's RayCaster: a caster that only casts single rays says so when asked for whole texels, warns
    of nothing, and credits its own rays; the report's words follow the Ray Caster items' labels."""
    import numpy as np

    from seamless_ao.core.rays.ray_setup import BVHCaster, RayCaster
    from seamless_ao.core.settings import caster_words

    caster = BVHCaster(np.eye(3), np.array([[0, 1, 2]]))
    assert isinstance(caster, RayCaster) and BVHCaster.name in {item[0] for item in CASTER_ITEMS}
    assert not caster.bakes_whole_texels and list(caster.warnings) == [] and caster.pilot_name == BVHCaster.name
    with pytest.raises(NotImplementedError, match="PYTHON_BVH caster casts single rays only"):
        caster.ambient_occlusion(np.zeros((1, 3)), np.zeros((1, 3)), np.zeros((1, 3)), 4, None)
    assert caster_words("PYTHON_BVH") == "Python BVH"
    assert caster_words("CYCLES") == "Geometry Nodes (first rays) and Cycles"
