"""The add-on as Blender sees it: manifest, built zip, install, enable/disable."""

import json
import pathlib
import re
import sys
import tomllib
import zipfile

import bpy
import pytest

from extension_zip import build_zips, build_zips_as_the_readme, run_tool
from package import ROOT, run_script, seamless_ao


def manifest():
    with open(ROOT / "blender_manifest.toml", "rb") as handle:
        return tomllib.load(handle)


def test_manifest_validates():
    proc = run_tool("validate", str(ROOT))
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_manifest_identity_and_license():
    data = manifest()
    assert data["id"] == "seamless_ao"
    assert data["name"] == "Seamless AO"
    assert data["blender_version_min"] == "4.2.0"
    assert data["license"] == ["SPDX:GPL-3.0-or-later"]


def test_manifest_wheels_cover_every_platform_and_python():
    """One xatlas wheel per listed platform, for Python 3.11 and 3.13 each."""
    data = manifest()
    tags = {"linux-x64": "manylinux", "windows-x64": "win_amd64", "macos-arm64": "macosx_11_0_arm64"}
    assert sorted(data["platforms"]) == sorted(tags)
    wheels = [pathlib.PurePosixPath(w).name for w in data["wheels"]]
    for platform, tag in tags.items():
        for py in ("cp311", "cp313"):
            assert any(py in w and tag in w for w in wheels), (platform, py, wheels)


def test_wheels_listed_are_downloaded():
    """`make extension` (and `make test`) download exactly the listed wheels."""
    missing = [w for w in manifest()["wheels"] if not (ROOT / w).is_file()]
    assert not missing, "run `make wheels/.downloaded`; missing: {}".format(missing)


@pytest.fixture(scope="module")
def built_zip(tmp_path_factory):
    zips = build_zips(tmp_path_factory.mktemp("dist"))
    assert len(zips) == 3, zips
    return zips["linux_x64"]


def test_zip_contains_the_package_and_not_the_tests(built_zip):
    names = zipfile.ZipFile(built_zip).namelist()
    assert "blender_manifest.toml" in names
    assert "__init__.py" in names
    assert "LICENSE" in names
    assert not any(n.endswith(".downloaded") for n in names)
    assert any(n.startswith("core/") for n in names)
    assert not any(n.startswith(("tests/", ".git", ".venv", "out/")) for n in names), names
    python = "cp{}{}".format(*sys.version_info[:2])
    assert any(re.search(r"wheels/xatlas-.*{}.*manylinux".format(python), n) for n in names), names



def test_the_plain_python_build_makes_the_zips_blenders_tool_makes(built_zip, tmp_path):
    """build.py (Python alone: no make, no Blender, as on Windows) writes the three platform zips with the same
    files, byte for byte, as Blender's own extension tool (``make extension``); the manifest it writes into
    each names that platform and its wheels only, and the build script is not in the zip."""
    ours = sorted(build_zips_as_the_readme(tmp_path).values())
    assert [path.name for path in ours] == sorted(path.name for path in built_zip.parent.glob("*.zip"))
    assert len(ours) == 3
    for path in ours:
        mine, blenders = zipfile.ZipFile(path), zipfile.ZipFile(built_zip.parent / path.name)
        assert sorted(mine.namelist()) == sorted(blenders.namelist()), path.name
        different = [name for name in mine.namelist() if mine.read(name) != blenders.read(name)]
        assert not different, (path.name, different)
        assert "build.py" not in mine.namelist()
        platform = path.stem.rsplit("-", 1)[1].replace("_", "-")
        generated = tomllib.loads(mine.read("blender_manifest.toml").decode())["build"]["generated"]
        assert generated["platforms"] == [platform] and len(generated["wheels"]) == 2

def test_zip_installs_enables_and_round_trips(built_zip):
    proc = run_script("install_zip.py", str(built_zip))
    lines = [l for l in proc.stdout.splitlines() if l.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-4000:] + proc.stderr[-4000:]
    result = json.loads(lines[-1][len("RESULT "):])
    assert result["install"] == ["FINISHED"]
    assert result["enabled_after_install"]
    assert result["operator_after_install"]
    assert result["scene_property"]
    assert result["bundled_xatlas"], "the xatlas wheel was not unpacked on install"
    assert result["cycle"] == [["disabled", False], ["enabled", True]] * 2


def test_register_unregister_repeatedly_leaks_nothing():
    before = set(dir(bpy.types))
    for _ in range(3):
        seamless_ao.register()
        assert hasattr(bpy.types, "OBJECT_OT_seamless_ao_bake")
        assert hasattr(bpy.types.Scene, "seamless_ao")
        seamless_ao.unregister()
        assert not hasattr(bpy.types, "OBJECT_OT_seamless_ao_bake")
        assert not hasattr(bpy.types.Scene, "seamless_ao")
    assert set(dir(bpy.types)) == before
