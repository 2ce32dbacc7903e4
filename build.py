"""Build the Seamless AO extension zips with plain Python 3.11 or later: no make, no Blender.

    python build.py                            # dist/seamless_ao-<version>-<platform>.zip, one per platform
    python build.py --platform windows_x64     # one of linux_x64, windows_x64, macos_arm64

Works the same on Windows, macOS and Linux. It downloads the xatlas wheels that blender_manifest.toml lists
into wheels/ with pip (once; those already there are kept), then writes one zip per platform as Blender's
own tool does (``blender --command extension build --split-platforms``): the files the manifest's
``[build] paths_exclude_pattern`` keeps, that platform's wheels, and the manifest with a ``[build.generated]``
table naming them. ``tests/blender/test_extension.py`` holds its zips to Blender's tool's, file for file.
Install a zip in Blender: Edit > Preferences > Get Extensions > Install from Disk.
"""

import argparse
import fnmatch
import pathlib
import subprocess
import sys
import tomllib
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent
#: A wheel's platform tag -> the manifest's platform it serves.
WHEEL_PLATFORMS = {"manylinux": "linux-x64", "win_amd64": "windows-x64", "macosx": "macos-arm64"}
GENERATED = ("\n\n# BEGIN GENERATED CONTENT.\n# This must not be included in source manifests.\n[build.generated]\n"
             "platforms = [{platforms}]\nwheels = [{wheels}]\n# END GENERATED CONTENT.\n")


def wheel_platform(name):
    """The manifest platform (``linux-x64`` …) a wheel file ``name`` is built for."""
    tag = name[:-len(".whl")].rsplit("-", 1)[1]
    return next(platform for prefix, platform in WHEEL_PLATFORMS.items() if tag.startswith(prefix))


def download_wheels(manifest, wheels_dir):
    """pip-download every wheel the manifest lists that ``wheels_dir`` lacks (by its file name's tags)."""
    for entry in manifest["wheels"]:
        path = ROOT / entry
        if path.is_file():
            continue
        name, version, python, _, tag = path.name[:-len(".whl")].split("-")
        platform = tag.split(".")[0]
        print("downloading", path.name)
        subprocess.run([sys.executable, "-m", "pip", "download", "--quiet", "--only-binary=:all:", "--no-deps",
                        "--python-version", python[2:], "--platform", platform, "-d", str(wheels_dir),
                        "{}=={}".format(name, version)], check=True)
        if not path.is_file():
            raise SystemExit("pip did not fetch {}".format(path.name))


def excluded(relative, is_dir, patterns):
    """Whether the path ``relative`` (posix, from the root) is left out by the gitignore-style ``patterns``."""
    parts = relative.split("/")
    for pattern in patterns:
        dir_only = pattern.endswith("/")
        body = pattern.strip("/")
        if dir_only and not is_dir:
            continue
        if pattern.startswith("/"):
            if fnmatch.fnmatchcase(relative, body):
                return True
        elif fnmatch.fnmatchcase(parts[-1], body):
            return True
    return False


def package_files(patterns):
    """Every file of the package the patterns keep, as posix paths from the root, wheels left out."""
    found = []

    def walk(folder):
        for path in sorted(folder.iterdir()):
            relative = path.relative_to(ROOT).as_posix()
            if path.is_symlink() or excluded(relative, path.is_dir(), patterns):
                continue
            if path.is_dir():
                walk(path)
            elif not relative.startswith("wheels/"):
                found.append(relative)

    walk(ROOT)
    return found


def build_zip(manifest, manifest_text, platform, files, out_dir):
    """Write ``<id>-<version>-<platform>.zip`` for the manifest platform ``platform``; its path."""
    wheels = [entry for entry in manifest["wheels"] if wheel_platform(entry) == platform]
    generated = GENERATED.format(platforms='"{}"'.format(platform),
                                 wheels=", ".join('"{}"'.format(entry) for entry in wheels))
    path = out_dir / "{}-{}-{}.zip".format(manifest["id"], manifest["version"], platform.replace("-", "_"))
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("blender_manifest.toml", manifest_text + generated)
        for entry in wheels:
            archive.write(ROOT / entry, entry[2:] if entry.startswith("./") else entry, zipfile.ZIP_STORED)
        for relative in files:
            if relative != "blender_manifest.toml":
                archive.write(ROOT / relative, relative)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--platform", action="append", choices=["linux_x64", "windows_x64", "macos_arm64"],
                        help="build for this platform only (may be given more than once; default: every one)")
    parser.add_argument("--output-dir", type=pathlib.Path, default=ROOT / "dist")
    args = parser.parse_args(argv)
    if sys.version_info < (3, 11):
        raise SystemExit("build.py needs Python 3.11 or later (it reads the manifest with tomllib)")
    manifest_text = (ROOT / "blender_manifest.toml").read_text(encoding="utf-8")
    manifest = tomllib.loads(manifest_text)
    download_wheels(manifest, ROOT / "wheels")
    files = package_files(manifest["build"]["paths_exclude_pattern"])
    args.output_dir.mkdir(parents=True, exist_ok=True)
    platforms = [p.replace("_", "-") for p in args.platform] if args.platform else manifest["platforms"]
    for platform in platforms:
        print("created", build_zip(manifest, manifest_text, platform, files, args.output_dir))


if __name__ == "__main__":
    main()
