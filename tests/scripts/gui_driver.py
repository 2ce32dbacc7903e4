"""What an artist does in Blender's window, driven with the mouse and keyboard (xdotool) under Xvfb:

    blender --factory-startup --python gui_driver.py -- SCENARIO OUT_DIR ZIP [ARGUMENTS]

Runs inside the real Blender of ``tests/support/real_blender.py``; writes ``OUT_DIR/result.json`` (what
each step saw, read from Blender's data) and a screenshot per step (``OUT_DIR/NN_step.png``), then quits.
Clicks go where the regions' geometry and the buttons themselves say: a tab is found by clicking down the
sidebar's tab strip until the region's category is ours, a button by hovering down the sidebar and asking
Blender with Ctrl+C (an operator button copies its Python command) or Ctrl+Shift+C (a property copies its
data path), a sub-panel header by the disclosure triangles in a screenshot.

Scenarios: ``artist`` (install, tab, Bake, Esc, Ctrl+Z, Preview AO Only, Clear, Export, save) and
``freeze SCENE BAKER`` (one bake at the defaults while a 50 ms timer counts how often the interface was
free; the bench's, ``tests/bench/bench_window.py``).
"""

import json
import os
import subprocess
import sys
import time
import traceback

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "support"))
import panel_fit  # noqa: E402

SCENARIO, OUT, ZIP = sys.argv[sys.argv.index("--") + 1:][:3]
TICK = 0.05
result = {"steps": []}
ticks = []


# -- seeing and touching the window -------------------------------------------------------------

def areas(kind):
    return [area for area in bpy.context.window.screen.areas if area.type == kind]


def regions():
    """``(3D view area, its main region, its sidebar)``."""
    area = areas("VIEW_3D")[0]
    return area, next(r for r in area.regions if r.type == "WINDOW"), next(r for r in area.regions if r.type == "UI")


def to_screen(region, x, y):
    """Screen pixel (origin top left) of region pixel ``(x, y)`` (origin bottom left)."""
    return int(region.x + x), int(bpy.context.window.height - (region.y + y))


def xdotool(*words):
    subprocess.run(["xdotool", *map(str, words)], check=True)


def hover(region, x, y):
    xdotool("mousemove", *to_screen(region, x, y))


def click(region, x, y):
    hover(region, x, y)
    xdotool("click", "1")


def key(combo, region=None):
    """Press ``combo`` (xdotool's names) with the mouse over ``region`` (default: the 3D view)."""
    region = region or regions()[1]
    hover(region, region.width / 2, region.height / 2)
    xdotool("key", combo)


def shot(name):
    """A screenshot of the whole screen (``bpy.ops.screen.screenshot`` gives black under Xvfb)."""
    path = os.path.join(OUT, "{:02d}_{}.png".format(len(result["steps"]), name))
    subprocess.run(["import", "-window", "root", path], check=True)
    return path


def step(name, **seen):
    result["steps"].append(dict(seen, step=name))
    with open(os.path.join(OUT, "result.json"), "w") as handle:
        json.dump(result, handle, indent=1)


def tick():
    """A 50 ms timer: its gaps are how long the interface could not run Python timers (a freeze)."""
    ticks.append(time.monotonic())
    return TICK


def freezes(since):
    """``(timer runs, longest gap in s)`` since ``since`` (monotonic)."""
    times = [t for t in ticks if t >= since]
    gaps = [b - a for a, b in zip(times, times[1:])]
    return len(times), (max(gaps) if gaps else None)


def unit():
    """Blender's interface unit in pixels at this window's scale."""
    return 20 * bpy.context.preferences.system.ui_scale


# -- finding what to click ------------------------------------------------------------------------

def open_tab(category="Seamless AO"):
    """Click down the sidebar's tab strip until ``category`` is the region's; raises if none is."""
    _, _, ui = regions()
    y = ui.height - 0.5 * unit()
    while ui.active_panel_category != category:
        if y < 0:
            raise RuntimeError("no sidebar tab {!r}".format(category))
        click(ui, ui.width - 0.5 * unit(), y)
        y -= 0.6 * unit()
        yield 0.3


def find(wanted, x_fraction=0.5, copy="ctrl+c"):
    """The sidebar height (region pixels) of the button whose Ctrl+C (operator: its Python command) or
    Ctrl+Shift+C (property: its data path) text contains ``wanted``, hovering down from the top."""
    _, _, ui = regions()
    window_manager = bpy.context.window_manager
    y = ui.height - 0.3 * unit()
    while y > 0:
        window_manager.clipboard = "-"             # Blender ignores an empty string here
        hover(ui, ui.width * x_fraction, y)
        yield 0.08                                # the button under the mouse is known once the move is handled
        xdotool("key", copy)
        yield 0.12
        result.setdefault("probes", []).append([wanted, round(y), window_manager.clipboard[:60]])
        if wanted in window_manager.clipboard:
            return y
        y -= 0.45 * unit()
    raise RuntimeError("no button {!r} in the sidebar".format(wanted))


def choose(name, value, x_fraction=0.75):
    """Set the scene's setting ``name`` (a menu) to ``value`` with Ctrl+Wheel over its button, as a user can:
    up until it shows, else down; returns the button's sidebar height."""
    settings = bpy.context.scene.seamless_ao
    y = yield from find("seamless_ao." + name, x_fraction, copy="ctrl+shift+c")
    _, _, ui = regions()
    for wheel in (4,) * 4 + (5,) * 8:                 # button 4: wheel up, 5: down
        if getattr(settings, name) == value:
            break
        hover(ui, ui.width * x_fraction, y)
        xdotool("keydown", "ctrl", "click", wheel, "keyup", "ctrl")
        yield 0.2
    return y


def press(wanted, x_fraction=0.5, copy="ctrl+c"):
    y = yield from find(wanted, x_fraction, copy)
    _, _, ui = regions()
    click(ui, ui.width * x_fraction, y)
    yield 0.3


def header_rows(below):
    """Sidebar heights (region pixels, top first) of the rows below height ``below`` where a screenshot
    shows something bright at the panels' left edge: disclosure triangles and the boxes' icons; the last
    is the last sub-panel's header."""
    path = shot("headers")
    image = bpy.data.images.load(path)
    width, height = image.size
    pixels = list(image.pixels)                   # RGBA rows, bottom first
    bpy.data.images.remove(image)
    _, _, ui = regions()
    x0, x1 = int(ui.x + 0.3 * unit()), int(ui.x + 2.2 * unit())
    rows = []
    for y in range(int(below) - 1, 0, -1):
        screen_row = ui.y + y                     # the image's rows count from the bottom, as regions do
        line = pixels[4 * (screen_row * width + x0):4 * (screen_row * width + x1)]
        bright = any(line[i] > 0.6 for i in range(0, len(line), 4))
        if bright and (not rows or rows[-1][1] != y + 1):
            rows.append([y, y])
        elif bright:
            rows[-1][1] = y
    return [(top + bottom) / 2 for top, bottom in rows]


# -- what the tests compare -----------------------------------------------------------------------

def cut_in_the_sidebar():
    """The sidebar's width, the interface's scale, and the texts of the installed extension's panels that
    do not fit that width (``tests/support/panel_fit.py``)."""
    area, _, ui = regions()
    sidebar = next(module for name, module in sys.modules.items()
                   if name.startswith("bl_ext.") and name.endswith(".panels.sidebar"))
    with bpy.context.temp_override(area=area, region=ui):
        return {"sidebar_width": ui.width, "ui_scale": bpy.context.preferences.system.ui_scale,
                "cut": panel_fit.cut_texts(sidebar, ui.width, context=bpy.context)}


def fingerprint():
    """Every datablock a bake could touch, by name, with the UV maps, attributes and material nodes."""
    return {"objects": sorted(bpy.data.objects.keys()), "images": sorted(bpy.data.images.keys()),
            "node_groups": sorted(bpy.data.node_groups.keys()),
            "meshes": {m.name: [[u.name for u in m.uv_layers], [a.name for a in m.attributes]]
                       for m in bpy.data.meshes},
            "materials": {m.name: sorted(n.name for n in m.node_tree.nodes) if m.node_tree else []
                          for m in bpy.data.materials},
            "modifiers": {o.name: [m.name for m in o.modifiers] for o in bpy.data.objects}}


def recent_reports():
    """The window's report lines, as the Info editor lists them (the timeline shows Info for a moment)."""
    area = areas("DOPESHEET_EDITOR")[0] if areas("DOPESHEET_EDITOR") else areas("TIMELINE")[0]
    kind, ui_type = area.type, area.ui_type
    area.type = "INFO"
    region = next(r for r in area.regions if r.type == "WINDOW")
    with bpy.context.temp_override(area=area, region=region):
        bpy.ops.info.select_all(action="SELECT")
        bpy.ops.info.report_copy()
    area.type, area.ui_type = kind, ui_type
    return [line for line in bpy.context.window_manager.clipboard.splitlines() if line.strip()]


def redo_panel_shown():
    """Whether the 3D view shows the redo panel (Adjust Last Operation): its HUD region has a size."""
    area = regions()[0]
    return any(r.type == "HUD" and r.width > 1 and r.height > 1 for r in area.regions)


def baking():
    """Whether our modal bake runs (``Window.modal_operators``, Blender 4.2+)."""
    return any(op.bl_idname == "OBJECT_OT_seamless_ao_bake" for op in bpy.context.window.modal_operators)


def wait_for_bake(limit=600):
    """Yield until the modal bake has ended; ``(seconds, timer runs, longest freeze)``."""
    started = time.monotonic()
    while not baking() and time.monotonic() - started < 5:
        yield 0.05
    while baking():
        if time.monotonic() - started > limit:
            raise RuntimeError("the bake did not end in {} s".format(limit))
        yield 0.1
    runs, longest = freezes(started)
    return time.monotonic() - started, runs, longest


# -- scenarios --------------------------------------------------------------------------------------

def the_scene():
    """Suzanne with Blender's default Subdivision (viewport 1, render 2), smooth, on a plane; both selected."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 1.0))
    suzanne = bpy.context.active_object
    suzanne.modifiers.new("Subdivision", "SUBSURF")
    bpy.ops.object.shade_smooth()
    bpy.ops.mesh.primitive_plane_add(size=6.0)
    suzanne.select_set(True)
    bpy.context.view_layer.objects.active = suzanne
    return suzanne, bpy.data.objects["Plane"]


def start_window():
    """The sidebar shown, the view on the selection, the splash closed."""
    area, window, _ = regions()
    area.spaces.active.show_region_ui = True
    with bpy.context.temp_override(area=area, region=window):
        bpy.ops.view3d.view_selected()
    key("Escape")
    bpy.ops.ed.undo_push(message="The scene")


def artist():
    install = bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
    step("install", result=sorted(install), registered=hasattr(bpy.types, "OBJECT_OT_seamless_ao_bake"))
    suzanne, plane = the_scene()
    settings = bpy.context.scene.seamless_ao
    settings.rays, settings.image_size = 16, 256          # Custom's knobs, for the bakes below that use them
    start_window()
    yield 1.0
    yield from open_tab()
    step("tab", category=regions()[2].active_panel_category, screenshot=shot("panel"))
    quality_at = yield from choose("quality", "DRAFT")   # a quick bake: the bench times the defaults
    bake_at = yield from find("seamless_ao_bake()")
    step("quality", quality=settings.quality, quality_at=quality_at, bake_at=bake_at)

    yield from press("seamless_ao_bake()")
    seconds, runs, longest = yield from wait_for_bake()
    step("bake", seconds=seconds, timer_runs=runs, longest_freeze=longest, plane_uv=plane.data.uv_layers.keys(),
         image=plane.get("seamless_ao_image"), last_bake_time=settings.last_bake_time,
         last_bake_quality=settings.last_bake_quality,
         redo_panel=redo_panel_shown(), **cut_in_the_sidebar(),
         reports=recent_reports(), screenshot=shot("baked"))

    before = fingerprint()
    settings.quality, settings.rays = "CUSTOM", 256      # long enough to be stopped midway
    yield from press("seamless_ao_bake()")
    while not baking():
        yield 0.05
    yield 1.5
    pressed = time.monotonic()
    key("Escape")
    while baking() and time.monotonic() - pressed < 30:
        yield 0.02
    step("escape", seconds_to_stop=time.monotonic() - pressed, unchanged=fingerprint() == before,
         before=before, after=fingerprint(), reports=recent_reports()[-3:], screenshot=shot("cancelled"))
    settings.rays = 16

    key("ctrl+z")
    yield 1.0
    plane = bpy.data.objects["Plane"]
    step("undo", plane_uv=plane.data.uv_layers.keys(), images=bpy.data.images.keys(), screenshot=shot("undone"))

    yield from press("seamless_ao_bake()")
    yield from wait_for_bake()
    yield from press("seamless_ao.preview", x_fraction=0.75, copy="ctrl+shift+c")
    area, window, _ = regions()
    with bpy.context.temp_override(area=area, region=window):   # Suzanne from the front, filling the view
        bpy.ops.view3d.view_axis(type="FRONT")
        bpy.ops.view3d.view_selected()
    area.spaces.active.shading.type = "MATERIAL"
    yield 1.0
    compiling = time.monotonic()
    while bpy.app.is_job_running("SHADER_COMPILATION") and time.monotonic() - compiling < 120:
        yield 0.5
    yield 1.0
    step("preview", preview=bpy.context.scene.seamless_ao.preview, screenshot=shot("preview"))
    area.spaces.active.shading.type = "SOLID"
    yield from press("seamless_ao.preview", x_fraction=0.75, copy="ctrl+shift+c")
    yield 2.0

    _, _, ui = regions()
    headers = header_rows(below=ui.height)
    click(ui, ui.width / 2, headers[-1])                  # the last sub-panel: Export
    yield 0.5
    hover(ui, ui.width / 2, ui.height / 2)
    for _ in range(20):                                   # what it opened is below the region's bottom
        xdotool("click", "5")
    yield 0.5
    yield from press("seamless_ao_resample(")
    yield 1.0
    exported = [name for name in bpy.data.images.keys() if "_AO_UVMap" in name]
    step("export", headers=len(headers), images=exported, screenshot=shot("exported"))

    hover(ui, ui.width / 2, ui.height / 2)
    for _ in range(20):                                   # back to the top of the sidebar
        xdotool("click", "4")
    yield 0.5
    yield from press("seamless_ao_clear(", x_fraction=0.25)
    yield 0.5
    step("clear", fingerprint=fingerprint(), plane_uv=bpy.data.objects["Plane"].data.uv_layers.keys(),
         redo_panel=redo_panel_shown(), screenshot=shot("cleared"))
    key("ctrl+z")                                         # the bake again, to be saved
    yield 1.0
    path = os.path.join(OUT, "artist.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    step("save", path=path, plane_uv=bpy.data.objects["Plane"].data.uv_layers.keys())


def dense_mesh():
    """Suzanne subdivided four times, applied: about 250,000 triangles, smooth; alone, selected."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 1.0))
    suzanne = bpy.context.active_object
    modifier = suzanne.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = 4
    bpy.ops.object.modifier_apply(modifier=modifier.name)
    bpy.ops.object.shade_smooth()
    return [suzanne]


def blenders_own_bake_ready(objects, size=1024, samples=64):
    """Blender's route: Smart UV Project, an image per object in its material, Cycles AO at ``samples``."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    for ob in objects:
        bpy.ops.object.select_all(action="DESELECT")
        ob.select_set(True)
        bpy.context.view_layer.objects.active = ob
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.uv.smart_project()
        bpy.ops.object.mode_set(mode="OBJECT")
        material = bpy.data.materials.new(ob.name + " baked")
        material.use_nodes = True
        node = material.node_tree.nodes.new("ShaderNodeTexImage")
        node.image = bpy.data.images.new(ob.name + " AO", size, size)
        material.node_tree.nodes.active = node
        ob.data.materials.clear()
        ob.data.materials.append(material)
    for ob in objects:
        ob.select_set(True)


def blender_baking():
    return bpy.app.is_job_running("OBJECT_BAKE")


def freeze():
    """One bake at the defaults, timed by the 50 ms timer: ``SCENE`` (suzanne: Suzanne with Blender's
    default Subdivision on a plane; dense: 250,000 triangles) baked by ``BAKER`` (ours, or blender: Smart
    UV Project and Cycles' AO bake, 1024², 64 samples, as Blender's own route)."""
    scene_kind, baker = sys.argv[sys.argv.index("--") + 1:][3:5]
    bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
    objects = list(the_scene()) if scene_kind == "suzanne" else dense_mesh()
    if baker == "blender":
        blenders_own_bake_ready(objects)
    start_window()
    yield 3.0
    area, window, _ = regions()
    started = time.monotonic()
    with bpy.context.temp_override(area=area, region=window):
        if baker == "blender":
            bpy.ops.object.bake("INVOKE_DEFAULT", type="AO")
        else:
            bpy.ops.object.seamless_ao_bake("INVOKE_DEFAULT")
    running = blender_baking if baker == "blender" else baking
    while not running() and time.monotonic() - started < 10:
        yield 0.05
    while running():
        yield 0.1
    runs, longest = freezes(started)
    triangles = sum(len(ob.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.loop_triangles)
                    for ob in objects)
    step("bake", scene=scene_kind, baker=baker, seconds=time.monotonic() - started, timer_runs=runs,
         longest_freeze=longest, triangles=triangles, screenshot=shot("{}_{}".format(scene_kind, baker)))


SCENARIOS = {"artist": artist, "freeze": freeze}


def drive(scenario=SCENARIOS[SCENARIO]()):
    """One timer callback per step of the scenario; quits Blender at its end or on any error."""
    try:
        return next(scenario)
    except StopIteration:
        result["done"] = True
    except Exception:
        result["error"] = traceback.format_exc()
    step("end")
    bpy.ops.wm.quit_blender()
    return None


os.makedirs(OUT, exist_ok=True)
bpy.app.timers.register(tick, first_interval=TICK, persistent=True)
bpy.app.timers.register(drive, first_interval=2.0, persistent=True)
