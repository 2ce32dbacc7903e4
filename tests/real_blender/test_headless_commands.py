"""Issue 57: every headless command of the README, docs/usage.md and docs/pipelines.md, as the user types it,
with a real ``blender`` binary and the extension installed from its zip by Blender's own installer.

The commands are read from the documents' ``sh`` blocks, so a command the docs add or change is run here
as written.  The one command that needs a Dask cluster (docs/pipelines.md, in a ``text`` block: its scheduler
address stands for the user's) runs in ``tests/blender/test_farm.py`` against a local cluster instead.  Each runs in a fresh copy of a folder holding the files the commands name
(``tests/scripts/documented_workspace.py``).
"""

import json
import pathlib
import re
import shlex
import shutil

import pytest

from gltf_checks import validate
from real_blender import BLENDER_PYTHON, BLENDER_VERSION, REPO

DOCUMENTS = ("README.md", "docs/usage.md", "docs/pipelines.md")
SCRIPTS = REPO / "tests" / "scripts"
AO_MAPS = ["AO_X", "AO_Y", "AO_Z"]


def documented_commands():
    """``[(document, command line)]``: each line of a ``sh`` block that starts with ``blender ``, a line
    ending in a backslash joined to the next, in the documents' order."""
    found = []
    for document in DOCUMENTS:
        text = (REPO / document).read_text(encoding="utf-8")
        for block in re.findall(r"```sh\n(.*?)```", text, flags=re.S):
            for line in block.replace("\\\n", " ").splitlines():
                line = line.split(" #", 1)[0].strip()
                if line.startswith("blender "):
                    found.append((document, " ".join(line.split())))
    return found


COMMANDS = documented_commands()
INSTALL = [command for _, command in COMMANDS if " extension install-file " in command]
SEAMLESS_AO = [(document, command) for document, command in COMMANDS if "--command seamless_ao " in command]


def test_the_documents_name_the_commands_this_file_runs():
    """The documents hold the install command and the bake, export, clear and batch commands."""
    assert len(INSTALL) == 1, COMMANDS
    actions = {shlex.split(command)[shlex.split(command).index("seamless_ao") + 1] for _, command in SEAMLESS_AO}
    assert actions == {"bake", "export", "clear", "batch"}, SEAMLESS_AO
    assert len(COMMANDS) == len(INSTALL) + len(SEAMLESS_AO), COMMANDS


def test_the_root_holds_the_blender_the_docs_name(real_blender):
    version = real_blender.run("blender", "--version")
    assert version.stdout.splitlines()[0] == "Blender " + BLENDER_VERSION, version.stdout[:500]
    python = real_blender.run("blender", "--background", "--factory-startup", "--python-expr",
                              "import sys; print('PYTHON', '{}.{}'.format(*sys.version_info[:2]))")
    assert "PYTHON " + BLENDER_PYTHON in python.stdout.splitlines(), python.stdout[-500:]


def describe(blender, path):
    """What the .blend at ``path`` holds (``tests/scripts/describe_blend.py``), read by the real Blender."""
    proc = blender.run("blender", "--background", "--factory-startup", "--python",
                       blender.inside(SCRIPTS / "describe_blend.py"), "--", blender.inside(path))
    lines = [line for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-3000:] + proc.stderr[-3000:]
    return json.loads(lines[-1][len("RESULT "):])


def extension_wheels(blender):
    """The xatlas files in the real Blender's extension wheel folder (its HOME is the scratch folder)."""
    return sorted(path.name for path in (blender.scratch / ".config").glob(
        "blender/*/extensions/.local/lib/python*/site-packages/xatlas*.so"))


@pytest.fixture(scope="session")
def installed(real_blender, zips):
    """The README's install command, run in the scratch folder where ``dist/`` holds the zips."""
    proc = real_blender.run(*shlex.split(INSTALL[0]))
    return proc


@pytest.fixture(scope="session")
def workspace(real_blender, installed):
    """The files the commands name, with ``baked.blend`` (what usage.md's second command writes) made by a
    quick bake, so that each command can run on its own."""
    folder = real_blender.scratch / "workspace"
    folder.mkdir()
    proc = real_blender.run("blender", "--background", "--factory-startup", "--python",
                            real_blender.inside(SCRIPTS / "documented_workspace.py"), cwd=folder)
    assert proc.returncode == 0 and (folder / "scene.blend").is_file(), proc.stdout[-3000:] + proc.stderr[-3000:]
    proc = real_blender.run("blender", "--background", "scene.blend", "--command", "seamless_ao", "bake", "--rays",
                            "8", "--image-size", "256", "--output", "baked.blend", cwd=folder)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return folder


def fresh_copy(workspace, tmp_path):
    """A copy of the workspace for one test, in the scratch folder the real Blender sees (named after
    the test's own ``tmp_path``)."""
    copy = workspace.parent / "runs" / tmp_path.name
    shutil.copytree(workspace, copy)
    return copy


def test_the_readme_install_command_installs_the_zip_with_its_wheel(real_blender, installed):
    assert installed.returncode == 0, installed.stdout[-3000:] + installed.stderr[-3000:]
    assert 'Installed "seamless_ao"' in installed.stdout + installed.stderr
    assert extension_wheels(real_blender), "the xatlas wheel was not unpacked into the extensions' site-packages"


def assert_baked(description, names):
    for name in names:
        ob = description["objects"][name]
        assert ob["uv_maps"][-3:] == AO_MAPS, (name, ob)
        image = description["images"][ob["ao_image"]]
        assert image["packed"] and image["finite"], image
        assert 0.0 <= image["min"] and image["max"] <= 1.0 and 0.2 < image["mean"] < 0.98, image


def check_bake(blender, folder, words):
    target = folder / (words[words.index("--output") + 1] if "--output" in words else words[2])
    names = ["Suzanne", "Floor"]                      # without --objects: the selected meshes, both
    if "--objects" in words:
        names = words[words.index("--objects") + 1:]
        names = names[:next((i for i, name in enumerate(names) if name.startswith("--")), len(names))]
    assert_baked(describe(blender, target), names)


def check_export(blender, folder, words):
    description = describe(blender, folder / words[2])
    name = words[words.index("--objects") + 1]
    uv_map = words[words.index("--uv-map") + 1]
    image = description["images"]["{}_AO_{}".format(name, uv_map)]
    size = int(words[words.index("--size") + 1])
    assert image["size"] == [size, size] and image["finite"] and 0.2 < image["mean"] < 0.98, image
    if "--color-attribute" in words:
        assert "AO" in description["objects"][name]["color_attributes"], description["objects"][name]


def check_clear(blender, folder, words):
    description = describe(blender, folder / words[2])
    ob = description["objects"][words[words.index("--objects") + 1]]
    assert not set(AO_MAPS) & set(ob["uv_maps"]) and "AO" not in ob["color_attributes"], ob


def check_batch(blender, folder, words, proc):
    lines = [line for line in proc.stderr.splitlines() if line.startswith("seamless_ao: [")]
    assert lines and all(" baked " in line or " skipped " in line for line in lines), proc.stderr[-3000:]
    out = folder / words[words.index("--output-dir") + 1] if "--output-dir" in words else folder
    glbs = sorted(out.rglob("*_ao.glb"))
    blends = sorted(out.rglob("*_ao.blend"))
    assert len(glbs) + len(blends) == len(lines), (lines, glbs, blends)
    reports = validate(glbs)
    assert all(reports[str(glb)]["errors"] == 0 for glb in glbs), reports
    for blend in blends:
        description = describe(blender, blend)
        baked = [name for name, ob in description["objects"].items() if ob["ao_image"]]
        assert baked, description
        assert_baked(description, baked)
    assert not (folder / "asset_ran_code.txt").exists(), "a batch ran the code an asset carries"
    if "--report" in words:
        report = json.loads((folder / words[words.index("--report") + 1]).read_text())
        assert report["counts"]["failed"] == 0 and report["counts"]["baked"] == len(lines), report["counts"]


CHECKS = {"bake": check_bake, "export": check_export, "clear": check_clear}


@pytest.mark.parametrize("document, command", SEAMLESS_AO,
                         ids=["{}: {}".format(d, c.split("seamless_ao ", 1)[1][:40]) for d, c in SEAMLESS_AO])
def test_the_documented_command_does_what_the_document_says(real_blender, workspace, tmp_path, document, command):
    folder = fresh_copy(workspace, tmp_path)
    proc = real_blender.run(*shlex.split(command), cwd=folder, timeout=900)
    assert proc.returncode == 0, "{}\n{}".format(command, proc.stderr[-3000:])
    words = shlex.split(command)
    action = words[words.index("seamless_ao") + 1]
    if action == "batch":
        check_batch(real_blender, folder, words, proc)
    else:
        CHECKS[action](real_blender, folder, words)
    assert extension_wheels(real_blender), "the extension's xatlas wheel is gone after: " + command


def test_help_lists_the_actions(real_blender, installed):
    proc = real_blender.run("blender", "--background", "--command", "seamless_ao", "--help")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert all(action in proc.stdout for action in ("bake", "clear", "export", "batch")), proc.stdout


def test_a_bad_value_exits_1_with_one_line_and_a_malformed_line_2(real_blender, workspace, tmp_path):
    folder = fresh_copy(workspace, tmp_path)
    proc = real_blender.run("blender", "--background", "scene.blend", "--command", "seamless_ao", "bake", "--rays",
                            "0", cwd=folder)
    ours = [line for line in proc.stderr.splitlines() if line.startswith("seamless_ao")]
    assert proc.returncode == 1 and len(ours) == 1 and "rays" in ours[0], proc.stderr
    assert "Traceback" not in proc.stderr + proc.stdout
    proc = real_blender.run("blender", "--background", "--command", "seamless_ao", "bake", "--no-such-option",
                            cwd=folder)
    assert proc.returncode == 2 and "unrecognized arguments: --no-such-option" in proc.stderr, proc.stderr


def test_a_failing_asset_is_reported_and_the_others_baked(real_blender, workspace, tmp_path):
    folder = fresh_copy(workspace, tmp_path)
    proc = real_blender.run("blender", "--background", "--command", "seamless_ao", "batch", "mixed/", "--output-dir",
                            "out/", "--jobs", "2", "--rays", "8", "--image-size", "256", "--report", "report.json",
                            cwd=folder)
    assert proc.returncode == 1, proc.stderr[-3000:]
    report = json.loads((folder / "report.json").read_text())
    status = {pathlib.Path(asset["input"]).name: asset["status"] for asset in report["assets"]}
    assert status == {"monkey.obj": "baked", "broken.glb": "failed", "edges.obj": "failed"}, report
    errors = {pathlib.Path(asset["input"]).name: asset["error"] for asset in report["assets"]}
    assert "could not read broken.glb" in errors["broken.glb"], errors
    assert "Traceback" not in errors["broken.glb"] + errors["edges.obj"]
    failed = [line for line in proc.stderr.splitlines() if line.startswith("seamless_ao: [") and " failed " in line]
    assert len(failed) == 2, proc.stderr
    glb = folder / "out" / "monkey_ao.glb"
    assert validate([glb])[str(glb)]["errors"] == 0
