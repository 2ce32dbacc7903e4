"""Does every text of the Seamless AO sidebar fit where Blender draws it?  Issue 51: labels cut with "..."
("Clear Seamless...") at the sidebar's default width.

Each panel's ``draw`` runs against :class:`RecordingLayout`, a stand-in for Blender's layout that notes each
label, button and setting and the share of the region's width it gets (a row shares its width among its
items; with property split a setting's name gets 40% and its value 60%).  :func:`cut_texts` measures each
text with ``blf`` in the interface's font and returns those wider than their share.  It runs in the
``bpy`` wheel (at :data:`DEFAULT_SIDEBAR_WIDTH`) and in a real window (at the region's own width).
"""

import importlib
import types

import bpy

#: The sidebar's width in pixels at UI scale 1 when Blender opens it: 291 pixels at the scale 1.0417 that
#: Blender 4.3.2 picks under Xvfb (tests/real_blender/test_gui.py measures it there).
DEFAULT_SIDEBAR_WIDTH = 279
#: Of a setting's row with property split, the share of its name (Blender draws the value in the rest).
SPLIT_SHARE = 0.4
#: Inside a button or field, the text keeps this many interface units from each edge; a checkbox, an
#: icon or a menu's arrow takes one unit.  Measured in that window: "Preview AO Only" fits its half row
#: with its icon and 2 pixels to spare, "Clear Seamless AO" (what the Clear button once said) did not.
PADDING_UNITS = 0.0


class RecordingLayout:
    """Records what a panel draws: ``(text, share of the usable width, units taken by icons)``."""

    def __init__(self, record, share=1.0, split=False, kind="column"):
        self.record, self.share, self.kind = record, share, kind
        self.use_property_split, self.use_property_decorate = split, False
        self.active = self.enabled = True
        self.scale_x = self.scale_y = 1.0
        self.items = []                            # a row's items get their share when the row is done

    def _child(self, kind):
        child = RecordingLayout(self.record, self.share, self.use_property_split, kind)
        self._add(child)
        return child

    def column(self, **_):
        return self._child("column")

    def row(self, **_):
        return self._child("row")

    def box(self):
        return self._child("box")

    def split(self, **_):
        return self._child("row")

    def separator(self, **_):
        pass

    def _add(self, item):
        self.items.append(item)

    def label(self, text="", icon="NONE", **_):
        self._add(("label", [text], icon != "NONE"))

    def operator(self, idname, text=None, icon="NONE", **_):
        if text is None:
            category, name = idname.split(".")
            text = getattr(bpy.types, "{}_OT_{}".format(category.upper(), name)).bl_label
        self._add(("button", [text], icon != "NONE"))
        return types.SimpleNamespace()

    def prop(self, data, name, text=None, toggle=False, icon="NONE", **_):
        rna = data.bl_rna.properties[name]
        text = rna.name if text is None else text
        if rna.type == "BOOLEAN" and toggle:
            self._add(("button", [text], icon != "NONE"))
        elif rna.type == "BOOLEAN":
            self._add(("checkbox", [text], True))
        elif rna.type == "ENUM":                   # its name, and any of its choices in the menu button
            self._add(("setting", [text, [item.name for item in rna.enum_items]], False))
        else:
            self._add(("setting", [text], False))

    def prop_search(self, data, name, *_, **__):
        self.prop(data, name)

    def measured(self, usable, text, scale):
        """``[(text, pixels it takes, pixels it has)]`` for everything under this layout (``text``: the
        add-on's ``panels.text`` module, whose measure the panels use)."""
        unit = text.UI_UNIT * scale
        width = usable - (0.5 * unit if self.kind == "box" else 0.0)
        # a row gives each item an equal part; a column, the whole
        parts = max(1, len(self.items)) if self.kind == "row" else 1
        out = []
        for item in self.items:
            if isinstance(item, RecordingLayout):
                out += item.measured(width / parts, text, scale)
                continue
            kind, texts, icon = item
            measure = text.text_width_px
            share = width / parts
            if kind == "setting" and self.use_property_split:
                # the name left of the split, the value (a menu: its choice and an arrow) right of it
                shares = [(texts[0], SPLIT_SHARE * share, False)]
                shares += [(choice, (1.0 - SPLIT_SHARE) * share, True) for choice in texts[1:][0]] if texts[1:] \
                    else []
            elif kind == "checkbox" and self.use_property_split:
                shares = [(texts[0], (1.0 - SPLIT_SHARE) * share, True)]
            else:
                shares = [(text, share, icon) for text in texts[:1]] + [
                    (choice, share, True) for choice in (texts[1] if texts[1:] else [])]
            for words, room, icon in shares:
                if words:
                    room -= 2 * PADDING_UNITS * unit + (unit if icon else 0.0)
                    out.append((words, measure(bpy.context, words), room))
        return out


def cut_texts(sidebar, region_width, context=None):
    """``[(panel, text, pixels it takes, pixels it has)]`` for each text of the add-on's sidebar panels that
    does not fit a sidebar ``region_width`` pixels wide.

    ``sidebar``: the add-on's ``panels.sidebar`` module (as the repository or as an installed extension);
    ``context``: what the panels' ``draw`` gets (default: ``bpy.context`` with a region of that width).
    """
    text = importlib.import_module(sidebar.__name__.rsplit(".", 1)[0] + ".text")
    if context is None:
        context = _ContextWithRegion(bpy.context, types.SimpleNamespace(width=region_width))
    scale = text.ui_scale(context)
    panels = [c for c in vars(sidebar).values() if isinstance(c, type) and issubclass(c, bpy.types.Panel)]
    cut = []
    for panel_class in panels:
        root = RecordingLayout([])
        panel_class.draw(_Drawing(panel_class, root), context)
        usable = region_width - text.MARGIN_UNITS * text.UI_UNIT * scale
        cut += [(panel_class.bl_label, words, round(needs), round(has))
                for words, needs, has in root.measured(usable, text, scale) if needs > has]
    return cut


class _Drawing:
    """Stands in for a panel instance (Blender makes those only to draw): its class's attributes, with
    methods bound to this object and ``layout`` the recording one."""

    def __init__(self, panel_class, layout):
        self._class, self.layout = panel_class, layout

    def __getattr__(self, name):
        for klass in self._class.__mro__:
            if name in vars(klass):
                found = vars(klass)[name]
                if isinstance(found, staticmethod):
                    return found.__func__
                return found.__get__(self) if callable(found) and hasattr(found, "__get__") else found
        raise AttributeError(name)


class _ContextWithRegion:
    """``bpy.context`` with another region (what the panels read its width from)."""

    def __init__(self, context, region):
        self._context, self.region = context, region

    def __getattr__(self, name):
        return getattr(self._context, name)
