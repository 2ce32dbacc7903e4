"""Headless use: ``blender --background scene.blend --command seamless_ao bake [options]``.

Registered with ``bpy.utils.register_cli_command``.  Every bake setting is an
option (``--rays 128``, ``--image-size 2048``, ``--ground-plane`` ...); options
not given take the scene's saved Seamless AO settings.  Exit code 0 on
success; otherwise a one-line reason on stderr and exit code 1 (2 for a bad
command line).
"""

import argparse
import sys

import bpy

from ..core.errors import SeamlessAOError
from ..core.settings import setting_fields
from . import api

PROG = "blender --background FILE.blend --command seamless_ao"


def option_name(field_name):
    return "--" + field_name.replace("_", "-")


def build_parser():
    parser = argparse.ArgumentParser(prog=PROG, description="Seamless AO: seamless ambient occlusion bakes.")
    actions = parser.add_subparsers(dest="action", required=True)
    bake = actions.add_parser("bake", help="bake AO for some mesh objects and (optionally) save the file")
    clear = actions.add_parser("clear", help="remove what Seamless AO added to some mesh objects")
    export_parser = actions.add_parser(
        "export", help="resample baked AO onto the objects' own UV map (glTF-ready) and/or a colour attribute")
    export_parser.add_argument("--uv-map", metavar="NAME", help="target UV map (default: the render-active one)")
    export_parser.add_argument("--size", type=int, default=1024, metavar="N", help="resampled image size")
    export_parser.add_argument("--padding", type=int, default=8, metavar="N", help="island dilation in texels")
    export_parser.add_argument("--gltf-occlusion", action=argparse.BooleanOptionalAction, default=True,
                               help="wire the image in as the glTF occlusion texture")
    export_parser.add_argument("--no-texture", action="store_true", help="skip the resampled texture")
    export_parser.add_argument("--color-attribute", choices=["CORNER", "POINT"],
                               help="also write colour attribute 'AO' on this domain")
    for sub in (bake, clear, export_parser):
        sub.add_argument("--objects", nargs="+", metavar="NAME",
                         help="mesh objects to use (default: the selected meshes, else the active object)")
        output = sub.add_mutually_exclusive_group()
        output.add_argument("--save", action="store_true", help="save the .blend file in place afterwards")
        output.add_argument("--output", metavar="FILE.blend", help="save the result as a new .blend file")
    for f in setting_fields():
        meta = f.metadata
        text = meta["description"]
        if "unit" in meta:
            text += " [{}]".format(meta["unit"])
        if isinstance(f.default, bool):
            bake.add_argument(option_name(f.name), action=argparse.BooleanOptionalAction, default=None, help=text)
        elif "items" in meta:
            bake.add_argument(option_name(f.name), choices=[item[0] for item in meta["items"]], default=None,
                              help=text)
        else:
            bake.add_argument(option_name(f.name), type=type(f.default), default=None, metavar="N", help=text)
    return parser


def resolve_objects(names):
    if names:
        names = [n for name in names for n in name.split(",") if n]
        missing = [n for n in names if n not in bpy.data.objects]
        if missing:
            meshes = sorted(ob.name for ob in bpy.data.objects if ob.type == "MESH")
            raise SeamlessAOError("no object named {} (mesh objects in this file: {})".format(
                ", ".join(repr(n) for n in missing), ", ".join(meshes) or "none"))
        return [bpy.data.objects[n] for n in names]
    view_layer = bpy.context.view_layer
    selected = [ob for ob in view_layer.objects if ob.select_get(view_layer=view_layer) and ob.type == "MESH"]
    if selected:
        return selected
    active = view_layer.objects.active
    if active is not None and active.type == "MESH":
        return [active]
    raise SeamlessAOError("nothing selected; name the objects to bake with --objects NAME [NAME ...]")


def run(argv):
    """The command's entry point: returns the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:
        return int(stop.code or 0)
    try:
        objects = resolve_objects(args.objects)
        if args.action == "bake":
            given = {f.name: getattr(args, f.name) for f in setting_fields() if getattr(args, f.name) is not None}
            if "max_distance" in given and "auto_distance" not in given:
                given["auto_distance"] = False          # an explicit distance means: use it
            report = api.bake(objects, progress=_print_progress, **given)    # the scene's settings, overridden
            print(report.summary())
            for warning in report.warnings:
                print("warning: " + warning)
        elif args.action == "export":
            from . import export
            if not args.no_texture:
                names = export.resample(objects, args.uv_map, args.size, args.padding, args.gltf_occlusion)
                print("Resampled AO into " + ", ".join(names))
            if args.color_attribute:
                export.to_color_attribute(objects, args.color_attribute)
                print("Wrote colour attribute 'AO' ({})".format(args.color_attribute.lower()))
        else:
            count = api.clear(objects)
            print("Cleared Seamless AO from {} object(s)".format(count))
        if args.save:
            if not bpy.data.filepath:
                raise SeamlessAOError("--save needs a file that was opened from disk; use --output FILE.blend")
            bpy.ops.wm.save_mainfile()
        elif args.output:
            bpy.ops.wm.save_as_mainfile(filepath=bpy.path.abspath(args.output))
    except SeamlessAOError as error:
        print("seamless_ao: error: {}".format(error), file=sys.stderr)
        return 1
    return 0


_last_printed = [-1]


def _print_progress(fraction, message):
    step = int(fraction * 10)
    if step != _last_printed[0]:
        _last_printed[0] = step
        print("seamless_ao: {:3.0f}% {}".format(100 * fraction, message), flush=True)


_handle = None


def register():
    global _handle
    if hasattr(bpy.utils, "register_cli_command"):
        _handle = bpy.utils.register_cli_command("seamless_ao", run)


def unregister():
    global _handle
    if _handle is not None:
        bpy.utils.unregister_cli_command(_handle)
        _handle = None
