"""Sentences in the sidebar that fit it: wrapped at words to the region's width, never cut off with "...".

    wrapped_labels(layout, context, "AO not shown on Suzanne: ...", icon="ERROR", in_box=True)
"""

import blf

#: Blender's interface unit (a widget's height, a panel's margins) in pixels at UI scale 1.
UI_UNIT = 20
#: What a panel and the region's tab strip take of the region's width, in interface units; a box takes
#: half a unit more, an icon one more.
MARGIN_UNITS = 3.0


def wrap_words(text, fits):
    """``text`` broken at spaces into lines for which ``fits(line)`` is true; a single word that does not
    fit stands alone on its line.

    Parameters
    ----------
    text : str
    fits : callable(str) -> bool

    Returns
    -------
    list of str, which joined with spaces give the words of ``text``
    """
    lines = []
    for word in text.split():
        if lines and fits(lines[-1] + " " + word):
            lines[-1] += " " + word
        else:
            lines.append(word)
    return lines


def ui_scale(context):
    """The interface's scale (1 where Blender runs without a window and gives 0)."""
    return context.preferences.system.ui_scale or 1.0


def text_width_px(context, text):
    """Width in pixels of ``text`` in the interface's label font at the interface's scale."""
    scale = ui_scale(context)
    blf.size(0, context.preferences.ui_styles[0].widget.points * scale)
    return blf.dimensions(0, text)[0]


def label_width_px(context, in_box=False, icon=False):
    """Pixels a label has for its text in this region (the sidebar, at its present width)."""
    scale = ui_scale(context)
    units = MARGIN_UNITS + (0.5 if in_box else 0.0) + (1.0 if icon else 0.0)
    return context.region.width - units * UI_UNIT * scale


def wrapped_lines(context, text, in_box=False, icon=False):
    """``text`` as the lines :func:`wrapped_labels` draws."""
    width = label_width_px(context, in_box, icon)
    return wrap_words(text, lambda line: text_width_px(context, line) <= width)


def wrapped_labels(layout, context, text, icon="NONE", in_box=False):
    """Draw ``text`` as labels, one per line that fits the region; the icon on the first, the others
    indented to match."""
    column = layout.column(align=True)
    for number, line in enumerate(wrapped_lines(context, text, in_box, icon != "NONE")):
        column.label(text=line, icon=icon if number == 0 else ("BLANK1" if icon != "NONE" else "NONE"))
