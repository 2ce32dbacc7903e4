"""Headless use: ``blender --background scene.blend --command seamless_ao bake [options]``.

Registered with ``bpy.utils.register_cli_command``.  Every bake setting is an
option (``--rays 128``, ``--image-size 2048``, ``--ground-plane`` ...), and so is
every export setting of the ``export`` command; options not given take the
scene's saved Seamless AO settings.  Exit code 0 on
success; otherwise a one-line reason on stderr and exit code 1 (2 for a bad
command line).  ``batch`` bakes files and folders of assets in worker
processes (``operators/batch/``): exit code 1 when any asset failed.
"""

import argparse
import sys

import bpy

from ...core.errors import SeamlessAOError
from ...core.settings import RESAMPLE_FIELDS, export_fields, gltf_fields, setting_fields
from ..adapters.clearing import clear
from ..adapters.exports import resample, to_color_attribute
from ..adapters.scene_settings import scene_export_settings
from ..adapters.session import bake
from ..batch.runner import batch

PROG = "blender --background FILE.blend --command seamless_ao"


def option_name(field_name):
    return "--" + field_name.replace("_", "-")


def build_parser():
    parser = argparse.ArgumentParser(prog=PROG, description="Seamless AO: seamless ambient occlusion bakes.")
    actions = parser.add_subparsers(dest="action", required=True)
    bake_parser = actions.add_parser("bake", help="bake AO for some mesh objects and (optionally) save the file")
    clear_parser = actions.add_parser("clear", help="remove what Seamless AO added to some mesh objects")
    export_parser = actions.add_parser(
        "export", help="resample baked AO onto the objects' own UV map (glTF-ready) and/or a colour attribute")
    add_options(export_parser, export_fields(RESAMPLE_FIELDS))
    export_parser.add_argument("--no-texture", action="store_true", help="skip the resampled texture")
    add_options(export_parser, [f for f in gltf_fields() if f.name == "color_attribute"])
    for sub in (bake_parser, clear_parser, export_parser):
        sub.add_argument("--objects", nargs="+", metavar="NAME",
                         help="mesh objects to use (default: the selected meshes, else the active object)")
        output = sub.add_mutually_exclusive_group()
        output.add_argument("--save", action="store_true", help="save the .blend file in place afterwards")
        output.add_argument("--output", metavar="FILE.blend", help="save the result as a new .blend file")
    add_options(bake_parser, setting_fields())
    add_batch_parser(actions)
    return parser


def add_batch_parser(actions):
    batch_parser = actions.add_parser(
        "batch", help="bake every asset of some files or folders (.blend, .glb/.gltf, .obj, .fbx, .ply, .stl) "
        "into .blend/.glb files, several at once")
    batch_parser.add_argument("paths", nargs="+", metavar="PATH", help="asset files, folders or glob patterns")
    batch_parser.add_argument("--glob", default="*", metavar="PATTERN",
                              help="file names to take inside folders (default: every asset type)")
    batch_parser.add_argument("--output-dir", metavar="DIR", help="write the results here (default: next to "
                              "each input, as NAME_ao.glb or NAME_ao.blend)")
    batch_parser.add_argument("--jobs", type=int, metavar="N", help="worker processes at once (default: cores)")
    batch_parser.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="bake on the workers of this Dask "
                              "scheduler instead, one task per asset (needs Dask: docs/pipelines.md)")
    batch_parser.add_argument("--force", action="store_true", help="bake even assets whose output is up to date")
    batch_parser.add_argument("--per-object", action="store_true", help="one AO image per object, not per asset")
    add_options(batch_parser, gltf_fields())
    batch_parser.add_argument("--new-uv", action="store_const", dest="uv_policy", const="new",
                              help="the same as --uv-policy new")
    batch_parser.add_argument("--report", metavar="FILE.json", help="write a JSON report, one record per asset")
    batch_parser.add_argument("--timeout", type=float, metavar="SECONDS",
                              help="stop an asset's worker after this long and report the asset failed")
    add_options(batch_parser, setting_fields())


def add_options(parser, fields):
    """One option per settings field (``--image-size N``, ``--ground-plane/--no-ground-plane`` ...), each
    defaulting to None: not given means the scene's saved setting."""
    for f in fields:
        meta = f.metadata
        text = meta["description"]
        if "unit" in meta:
            text += " [{}]".format(meta["unit"])
        if isinstance(f.default, bool):
            parser.add_argument(option_name(f.name), action=argparse.BooleanOptionalAction, default=None, help=text)
        elif "items" in meta:
            parser.add_argument(option_name(f.name), choices=[item[0] for item in meta["items"]], default=None,
                                help=text)
        else:
            parser.add_argument(option_name(f.name), type=type(f.default), default=None,
                                metavar="NAME" if isinstance(f.default, str) else "N", help=text)


def given_options(args, fields):
    """``{name: value}`` of the options the command line gave."""
    return {f.name: getattr(args, f.name) for f in fields if getattr(args, f.name) is not None}


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
        if args.action == "batch":
            return run_batch(args)
        objects = resolve_objects(args.objects)
        if args.action == "bake":
            report = bake(objects, progress=_print_progress, **bake_options(args))    # the scene's settings, overridden
            print(report.summary())
            for warning in report.warnings:
                print("warning: " + warning)
        elif args.action == "export":
            settings = scene_export_settings(bpy.context.scene).replace(
                **given_options(args, export_fields(RESAMPLE_FIELDS)))
            if not args.no_texture:
                names = resample(objects, **{name: getattr(settings, name) for name in RESAMPLE_FIELDS})
                print("Resampled AO into " + ", ".join(names))
            if args.color_attribute not in (None, "NONE"):
                to_color_attribute(objects, args.color_attribute, settings.material_strength)
                print("Wrote colour attribute 'AO' ({})".format(args.color_attribute.lower()))
        else:
            count = clear(objects)
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


def bake_options(args):
    """The bake settings the command line gave (an explicit ``--max-distance`` turns the automatic one off)."""
    given = given_options(args, setting_fields())
    if "max_distance" in given and "auto_distance" not in given:
        given["auto_distance"] = False
    return given


def run_batch(args):
    """``batch``: exit code 0 if every asset was baked or up to date, 1 if any failed, 2 if the request
    itself is wrong (a bad setting, paths that name no asset)."""
    try:
        records = batch(args.paths, output_dir=args.output_dir, jobs=args.jobs, pattern=args.glob,
                        force=args.force, per_object=args.per_object, report=args.report, timeout=args.timeout,
                        scheduler=args.scheduler, **bake_options(args), **given_options(args, gltf_fields()))
    except SeamlessAOError as error:
        print("seamless_ao: error: {}".format(error), file=sys.stderr)
        return 2
    counts = {status: sum(r.status == status for r in records) for status in ("baked", "skipped", "failed")}
    print("Batch: {baked} baked, {skipped} up to date, {failed} failed".format(**counts))
    return 1 if counts["failed"] else 0


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
