"""The extension zip as ``make extension`` builds it, with Blender's own tool from the ``bpy`` wheel.

    build_zips(out_dir) -> {platform: path}     e.g. {"linux_x64": .../seamless_ao-0.1.0-linux_x64.zip, ...}
    build_zips_as_the_readme(out_dir) -> the same, from ``python build.py`` (the README's install path)
"""

import pathlib
import subprocess
import sys

import bpy

ROOT = pathlib.Path(__file__).resolve().parents[2]


def blender_ext_tool():
    """``blender_ext.py``, the extension tool shipped in the ``bpy`` wheel (and in every Blender)."""
    scripts = pathlib.Path(bpy.utils.system_resource("SCRIPTS"))
    tool = scripts / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"
    assert tool.is_file(), "blender_ext.py not found in the bpy wheel at {}".format(tool)
    return tool


def run_tool(*args):
    """Run ``blender_ext.py ARGS`` in the repository; the finished process."""
    return subprocess.run(
        [sys.executable, str(blender_ext_tool()), *args], cwd=ROOT, capture_output=True, text=True, timeout=300)


def build_zips(out_dir):
    """Build one zip per platform into ``out_dir``, as ``make extension`` does; ``{platform: path}``."""
    pathlib.Path(out_dir).mkdir(parents=True, exist_ok=True)
    proc = run_tool("build", "--source-dir", str(ROOT), "--output-dir", str(out_dir), "--split-platforms")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return {path.stem.rsplit("-", 1)[1]: path for path in sorted(pathlib.Path(out_dir).glob("*.zip"))}


def build_zips_as_the_readme(out_dir):
    """The zips of the README's ``python build.py`` (plain Python, no Blender) in ``out_dir``; ``{platform: path}``."""
    proc = subprocess.run([sys.executable, str(ROOT / "build.py"), "--output-dir", str(out_dir)], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return {path.stem.rsplit("-", 1)[1]: path for path in sorted(pathlib.Path(out_dir).glob("*.zip"))}
