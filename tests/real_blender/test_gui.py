"""Issue 51: the artist's Blender, for real: a Blender window (Xvfb) driven with the mouse and keyboard by
``tests/scripts/gui_driver.py``, as a user does it: the zip installed with Blender's own installer, the
sidebar tab opened and Bake pressed with clicks, the modal bake on real timer events, Esc, Ctrl+Z, Preview
AO Only, Export and Clear from the panel, then the saved file rendered with the extension disabled.

Each step saves a screenshot; they are copied to ``out/gui/`` of the repository.
"""

import json
import shutil

import numpy as np
import pytest

from panel_fit import DEFAULT_SIDEBAR_WIDTH
from real_blender import REPO

SCRIPTS = REPO / "tests" / "scripts"
SCREENSHOTS = REPO / "out" / "gui"


@pytest.fixture(scope="module")
def artist(real_blender, zips):
    """The ``artist`` scenario, run once: ``{step name: what it saw}``, and the folder it wrote."""
    out = real_blender.scratch / "gui" / "artist"
    home = real_blender.scratch / "gui" / "home"
    home.mkdir(parents=True)
    with real_blender.display() as display:
        proc = real_blender.run(
            "blender", "--factory-startup", "--python", real_blender.inside(SCRIPTS / "gui_driver.py"), "--",
            "artist", real_blender.inside(out), real_blender.inside(zips["linux_x64"]),
            env=dict(display, HOME=real_blender.inside(home)), timeout=900)
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    for picture in sorted(out.glob("*.png")):
        shutil.copy(picture, SCREENSHOTS / picture.name)
    result = json.loads((out / "result.json").read_text())
    assert result.get("done"), "the driver stopped: {}\n{}".format(result.get("error"), proc.stderr[-3000:])
    return {entry["step"]: entry for entry in result["steps"]}, out, home


def test_blenders_installer_installs_the_zip_and_the_tab_opens_with_a_click(artist):
    steps, _, _ = artist
    assert steps["install"]["result"] == ["FINISHED"] and steps["install"]["registered"]
    assert steps["tab"]["category"] == "Seamless AO"


def test_quality_comes_first_and_a_user_can_choose_a_preset(artist):
    """Chosen with Ctrl+Wheel over the Quality menu, above the Bake button; the bake says what it took."""
    quality, bake = artist[0]["quality"], artist[0]["bake"]
    assert quality["quality"] == "DRAFT" and quality["quality_at"] > quality["bake_at"], quality
    assert bake["last_bake_quality"] == "Draft, 256², 4 rays", bake


def test_the_bake_button_bakes_on_timer_events_and_says_one_short_sentence(artist):
    bake = artist[0]["bake"]
    assert bake["plane_uv"][-3:] == ["AO_X", "AO_Y", "AO_Z"] and bake["image"], bake
    assert bake["last_bake_time"] > 0 and bake["timer_runs"] >= 3, bake
    ours = [line for line in bake["reports"] if "Seamless AO" in line]
    assert ours and ours[-1].startswith("Seamless AO baked") and len(ours[-1]) <= 60, bake["reports"]
    assert not any("Baking map" in line for line in bake["reports"]), "Cycles' messages reach the user"


def test_no_text_of_the_sidebar_is_cut_at_its_default_width(artist):
    """Every label, button, setting name and menu choice of every panel, measured with Blender's own font in
    the window's sidebar after a bake (Last bake box shown); the width is the one the bpy-wheel test
    assumes (tests/support/panel_fit.py)."""
    bake = artist[0]["bake"]
    assert bake["cut"] == [], bake["cut"]
    assert abs(bake["sidebar_width"] / bake["ui_scale"] - DEFAULT_SIDEBAR_WIDTH) <= 2, bake


def test_no_redo_panel_after_a_bake_and_one_after_clear(artist):
    """Adjust Last Operation would re-run the whole bake frozen: the bake does not offer it (Clear, quick,
    does, which shows the check can see it)."""
    steps = artist[0]
    assert not steps["bake"]["redo_panel"]
    assert steps["clear"]["redo_panel"]


def test_esc_midway_stops_the_bake_at_once_and_changes_nothing(artist):
    escape = artist[0]["escape"]
    assert escape["unchanged"], (escape["before"], escape["after"])
    assert escape["seconds_to_stop"] < 5, "Esc waited for the bake"
    assert any("nothing was changed" in line for line in escape["reports"]), escape["reports"]


def test_ctrl_z_takes_the_bake_back(artist):
    undo = artist[0]["undo"]
    assert undo["plane_uv"] == ["UVMap"], undo
    assert not any(name.endswith("_AO") for name in undo["images"]), undo


def test_preview_export_and_clear_from_the_panel(artist):
    steps = artist[0]
    assert steps["preview"]["preview"]
    assert sorted(steps["export"]["images"]) == ["Plane_AO_UVMap", "Suzanne_AO_UVMap"], steps["export"]
    clear = steps["clear"]
    assert clear["plane_uv"] == ["UVMap"]
    assert not any("Seamless" in name for name in clear["fingerprint"]["node_groups"]), clear["fingerprint"]
    assert steps["save"]["plane_uv"][-3:] == ["AO_X", "AO_Y", "AO_Z"]


def render(real_blender, home, blend, *options, factory=True):
    out = blend.parent / "render_{}_{}.npy".format("factory" if factory else "installed", len(options))
    proc = real_blender.run("blender", "--background", *(["--factory-startup"] if factory else []),
                            real_blender.inside(blend), "--python", real_blender.inside(SCRIPTS / "render_saved.py"),
                            "--", real_blender.inside(out), *options, env={"HOME": real_blender.inside(home)})
    assert proc.returncode == 0 and out.exists(), proc.stdout[-2000:] + proc.stderr[-2000:]
    return np.load(out)


def test_the_saved_file_renders_its_ao_with_the_extension_disabled(real_blender, artist):
    _, out, home = artist
    blend = out / "artist.blend"
    installed = render(real_blender, home, blend, factory=False)
    disabled = render(real_blender, home, blend)
    without_ao = render(real_blender, home, blend, "--without-ao")
    assert np.abs(installed - disabled).max() < 0.02, "the file renders otherwise without the extension"
    darkened = without_ao - disabled                      # where the AO darkens the render (under Suzanne)
    assert (darkened > 0.05).mean() > 0.02, "the render shows no AO"
