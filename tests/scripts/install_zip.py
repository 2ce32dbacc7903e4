"""Install a built extension zip into a fresh bpy and exercise enable/disable.

Run as a separate process (it registers the add-on under its real
``bl_ext.*`` name, which must not clash with the test session's copy):

    python install_zip.py path/to/seamless_ao.zip

Prints one JSON line with what it found; exits non-zero on failure.
"""

import json
import os
import shutil
import sys
import tempfile

os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="seamless_ao_install_")

import bpy  # noqa: E402


def operator_registered():
    return hasattr(bpy.types, "OBJECT_OT_seamless_ao_bake")


def main(zip_path):
    result = {"blender": bpy.app.version_string}
    repo = "user_default"
    op_result = bpy.ops.extensions.package_install_files(
        filepath=zip_path, repo=repo, enable_on_install=True)
    result["install"] = sorted(op_result)
    module = "bl_ext.{}.seamless_ao".format(repo)
    result["module"] = module
    result["enabled_after_install"] = module in bpy.context.preferences.addons
    result["operator_after_install"] = operator_registered()
    result["scene_property"] = hasattr(bpy.context.scene, "seamless_ao")
    # The bundled wheel is unpacked into the extensions' own site-packages.
    local = bpy.utils.user_resource("EXTENSIONS", path=".local")
    result["bundled_xatlas"] = sorted(
        os.path.relpath(os.path.join(d, f), local)
        for d, _, files in os.walk(local) for f in files if f.startswith("xatlas") and f.endswith((".so", ".pyd")))
    cycle = []
    for _ in range(2):
        bpy.ops.preferences.addon_disable(module=module)
        cycle.append(("disabled", operator_registered()))
        bpy.ops.preferences.addon_enable(module=module)
        cycle.append(("enabled", operator_registered()))
    result["cycle"] = cycle
    print("RESULT " + json.dumps(result))


if __name__ == "__main__":
    arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]    # Blender or Python
    main(os.path.abspath(arguments[0]))
    # bpy 4.2's module crashes in interpreter teardown after a PropertyGroup was registered: leave without it,
    # and without what it would remove (Blender's session folder) or no one would (the user resources)
    sys.stdout.flush()
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
    from launch_file import launcher
    launcher().remove_session_folder()
    shutil.rmtree(os.environ["BLENDER_USER_RESOURCES"], ignore_errors=True)
    os._exit(0)
