"""Issue 51: no sentence of the sidebar is cut off ("The modifiers here ...than the one baked."), and the
Last bake box pairs each label with its value."""

import types

import blf
import bpy

from package import seamless_ao
from panel_fit import DEFAULT_SIDEBAR_WIDTH, cut_texts

from seamless_ao.panels import sidebar
from seamless_ao.panels.sidebar import last_bake_rows
from seamless_ao.panels.text import wrap_words

SENTENCE = ("AO not shown on Suzanne, Suzanne.001: the modifiers give another surface than the one baked. "
            "Bake again.")


def test_wrapped_lines_fit_and_keep_every_word():
    blf.size(0, 11)
    for width in (120, 180, 240, 400):
        lines = wrap_words(SENTENCE, lambda line: blf.dimensions(0, line)[0] <= width)
        assert " ".join(lines) == " ".join(SENTENCE.split())
        assert all(blf.dimensions(0, line)[0] <= width for line in lines if " " in line), (width, lines)
        assert len(lines) > 1 or width == 400


def test_a_word_wider_than_the_line_stands_alone():
    assert wrap_words("a verylongword b", lambda line: len(line) <= 4) == ["a", "verylongword", "b"]


def test_the_last_bake_box_pairs_each_label_with_its_value(addon):
    settings = bpy.context.scene.seamless_ao
    settings.last_bake_time, settings.last_bake_texels, settings.last_bake_rays = 33.5, 836482, 53012032
    settings.last_bake_utilisation, settings.last_bake_noise = 0.76, 0.01
    settings.last_bake_quality = "Good, 256², 32 rays"
    assert last_bake_rows(settings) == [("Quality", "Good"), ("Image", "256², 32 rays"), ("Time", "33.5 s"),
                                        ("Texels", "836,482"), ("Rays", "53,012,032"),
                                        ("Atlas use", "76%"), ("Noise (raw, 1σ)", "≈ 0.010")]


def test_every_text_of_every_panel_fits_the_default_sidebar(addon):
    """Labels, buttons, settings' names and every choice of their menus, at the sidebar's default width, with
    the Last bake box at large figures (tests/support/panel_fit.py)."""
    settings = bpy.context.scene.seamless_ao
    settings.last_bake_summary, settings.last_bake_rays, settings.last_bake_texels = "baked", 53012032, 836482
    settings.last_bake_quality = "Custom, 8192², 4096 rays"
    assert cut_texts(sidebar, DEFAULT_SIDEBAR_WIDTH) == []


def test_the_fit_check_finds_a_cut_button(addon):
    """What the Clear button once said does not fit its half row (Blender showed "Clear Seamless...")."""
    class Once(bpy.types.Panel):
        bl_label = "Once"

        def draw(self, context):
            row = self.layout.row(align=True)
            row.operator("object.seamless_ao_clear", icon="TRASH")
            row.prop(context.scene.seamless_ao, "preview", toggle=True, icon="HIDE_OFF")

    once = types.ModuleType(sidebar.__name__.rsplit(".", 1)[0] + ".once")
    once.Once = Once
    assert bpy.types.OBJECT_OT_seamless_ao_clear.bl_label == "Clear Seamless AO"
    assert [text for _, text, _, _ in cut_texts(once, DEFAULT_SIDEBAR_WIDTH)] == ["Clear Seamless AO"]
