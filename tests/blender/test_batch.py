"""Issue 17: ``seamless_ao batch`` bakes a folder of assets, glTF in and glTF out, several at once."""

import json
import os
import pathlib
import shutil
import struct

import addon_utils
import bpy
import numpy as np
import pytest

from batch_assets import make_asset_folder, other_formats
from package import run_command, run_script, seamless_ao

FAST = ("--rays", "16", "--image-size", "256", "--texture-size", "256")
BAKED = {"with_uv": "with_uv_ao.glb", "no_uv": "no_uv_ao.glb", "obj": "monkey_ao.glb", "blend": "room_ao.blend"}


def run_batch(*args):
    proc = run_command("batch", *args)
    return proc, [line for line in proc.stderr.splitlines() if line.startswith("seamless_ao: [")]


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    """The six assets through ``batch --jobs 2`` once, with vertex colours and a report."""
    root = tmp_path_factory.mktemp("batch")
    marker = root / "the_asset_ran_code.txt"
    assets = make_asset_folder(root / "assets", marker)
    out, report = root / "out", root / "report.json"
    proc, lines = run_batch(str(root / "assets"), "--output-dir", str(out), "--jobs", "2", "--report", str(report),
                            "--color-attribute", "CORNER", *FAST)
    return dict(root=root, assets=assets, out=out, report=report, marker=marker, proc=proc, lines=lines)


def glb_json(path):
    """The JSON chunk of a .glb file."""
    data = path.read_bytes()
    length, kind = struct.unpack("<II", data[12:20])
    assert kind == 0x4E4F534A, "first chunk of {} is not JSON".format(path.name)
    return json.loads(data[20:20 + length])


def imported_occlusion(path):
    """Import a .glb with Blender's glTF importer; per mesh object: (corner values of the occlusion
    texture through the UV map it is wired to, corner values of COLOR_0, name of that UV map)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("io_scene_gltf2", default_set=False)
    bpy.ops.import_scene.gltf(filepath=str(path))
    found = {}
    for ob in [o for o in bpy.context.scene.objects if o.type == "MESH"]:
        tree = ob.active_material.node_tree
        group = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeGroup" and "Occlusion" in n.inputs)
        node = group.inputs["Occlusion"].links[0].from_node
        while node.bl_idname != "ShaderNodeTexImage":          # Separate Color, then the image
            node = next(i for i in node.inputs if i.is_linked).links[0].from_node
        vector = node.inputs["Vector"]
        uv_name = vector.links[0].from_node.uv_map if vector.is_linked else ob.data.uv_layers[0].name
        width, height = node.image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        node.image.pixels.foreach_get(pixels)
        image = pixels.reshape(height, width, 4)[:, :, 0].astype(np.float64)
        mesh = ob.data
        uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
        mesh.uv_layers[uv_name].data.foreach_get("uv", uv)
        through_texture = seamless_ao.core.image.shown.bilinear(image, uv.reshape(-1, 2).astype(np.float64))
        colour = mesh.color_attributes[0]
        colours = np.empty(len(colour.data) * 4, dtype=np.float32)
        colour.data.foreach_get("color", colours)
        colours = colours.reshape(-1, 4)[:, 0]
        if colour.domain == "POINT":
            vertex = np.empty(len(mesh.loops), dtype=np.int32)
            mesh.loops.foreach_get("vertex_index", vertex)
            colours = colours[vertex]
        found[ob.name] = (through_texture, colours, uv_name)
    return found


def test_one_command_bakes_the_folder_and_reports_each_asset(first_run):
    proc, out = first_run["proc"], first_run["out"]
    assert proc.returncode == 1, proc.stdout + proc.stderr          # two assets failed
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == sorted(BAKED.values())
    assert len(first_run["lines"]) == 6 and first_run["lines"][-1].startswith("seamless_ao: [6/6]")
    assert "Batch: 4 baked, 0 up to date, 2 failed" in proc.stdout
    report = json.loads(first_run["report"].read_text())
    records = {os.path.basename(r["input"]): r for r in report["assets"]}
    assert sorted(records) == sorted(p.name for p in first_run["assets"].values())
    assert records["broken.glb"]["status"] == "failed"
    assert records["broken.glb"]["error"].startswith("could not read broken.glb: ")
    assert records["edges.obj"]["status"] == "failed"
    assert "has no faces to bake (only vertices or loose edges)" in records["edges.obj"]["error"]
    for kind, name in BAKED.items():
        record = records[first_run["assets"][kind].name]
        assert record["status"] == "baked" and record["output"] == str(out / name), record
        assert record["triangles"] > 0 and record["texels"] > 0 and record["rays"] > record["texels"]
        assert 0.0 < record["noise"] < 0.5
        assert {"load", "charts", "rays", "export", "total"} <= set(record["seconds"])
    assert any("shared a mesh" in w for w in records["no_uv.glb"]["warnings"])      # the instanced cup
    assert report["counts"] == {"baked": 4, "skipped": 0, "failed": 2}


@pytest.mark.parametrize("kind", ["with_uv", "no_uv", "obj"])
def test_glb_carries_the_ao_as_occlusion_on_the_right_uv_map(first_run, kind):
    path = first_run["out"] / BAKED[kind]
    data = glb_json(path)
    assert data["materials"] and all("occlusionTexture" in m for m in data["materials"])
    for mesh in data["meshes"]:
        for primitive in mesh["primitives"]:
            occlusion = data["materials"][primitive["material"]]["occlusionTexture"]
            assert "TEXCOORD_{}".format(occlusion.get("texCoord", 0)) in primitive["attributes"]
            assert [k for k in primitive["attributes"] if k.startswith("TEXCOORD")] == ["TEXCOORD_0"]   # no AO_X/Y/Z
            assert "COLOR_0" in primitive["attributes"]
    found = imported_occlusion(path)
    assert len(found) == (3 if kind == "no_uv" else 2)
    darkest = 1.0
    for name, (through_texture, colour, uv_name) in found.items():
        # the texture read through the UV map it is wired to shows what the bake's colours say
        assert np.median(np.abs(through_texture - colour)) < 0.03, (name, uv_name)
        darkest = min(darkest, float(np.percentile(colour, 5)))
    assert darkest < 0.8                       # the pieces occlude each other: the AO is not blank


def test_every_glb_the_batch_wrote_passes_the_khronos_validator(first_run):
    from gltf_checks import validate
    written = sorted(first_run["out"].glob("*.glb"))
    assert len(written) == 3
    for path, report in validate(written).items():
        assert report["errors"] == 0 and report["warnings"] == 0, (path, report["messages"])


def test_blend_in_blend_out_without_running_the_assets_code(first_run):
    output = first_run["out"] / BAKED["blend"]
    assert not first_run["marker"].exists(), "the batch ran a script stored in the .blend"
    bpy.ops.wm.read_factory_settings(use_empty=True)
    with bpy.data.libraries.load(str(output)) as (source, target):
        target.meshes = list(source.meshes)
        images = list(source.images)
    assert any(name.endswith("_AO") for name in images), images
    assert all("AO_X" in mesh.uv_layers for mesh in target.meshes if mesh.polygons)
    # the same file opened with scripts allowed does write the marker: the check above can fail
    control = first_run["root"] / "control"
    control.mkdir()
    shutil.copy(first_run["assets"]["blend"], control / "room.blend")
    proc = run_script("open_blend.py", str(control / "room.blend"), "--allow-scripts")
    assert proc.returncode == 0, proc.stderr
    assert first_run["marker"].exists()
    first_run["marker"].unlink()


def test_a_second_run_skips_everything_and_a_changed_input_is_baked_again(first_run):
    out = first_run["out"]
    times = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    proc, lines = run_batch(str(first_run["root"] / "assets"), "--output-dir", str(out), "--jobs", "2",
                            "--color-attribute", "CORNER", *FAST)
    assert proc.returncode == 1
    assert "Batch: 0 baked, 4 up to date, 2 failed" in proc.stdout, proc.stdout + proc.stderr
    assert sum("skipped" in line for line in lines) == 4 and sum("(as before)" in line for line in lines) == 2
    assert all(p.stat().st_mtime_ns == times[p.name] for p in out.iterdir() if p.name in BAKED.values())
    # other settings are another result: baked again
    proc, _ = run_batch(str(first_run["assets"]["obj"]), "--output-dir", str(out), "--jobs", "1", *FAST)
    assert "Batch: 1 baked" in proc.stdout, proc.stdout + proc.stderr
    # so is an input newer than its output
    os.utime(first_run["assets"]["with_uv"])
    proc, _ = run_batch(str(first_run["assets"]["with_uv"]), "--output-dir", str(out), "--jobs", "1",
                        "--color-attribute", "CORNER", *FAST)
    assert "Batch: 1 baked" in proc.stdout, proc.stdout + proc.stderr


def test_odd_names_stay_inside_the_output_folder_with_new_uv_and_one_image_per_object(first_run, tmp_path):
    folder = tmp_path / "in" / "deep"
    folder.mkdir(parents=True)
    odd = folder / "..-$(touch x); name ü.glb"
    shutil.copy(first_run["assets"]["with_uv"], odd)
    out = tmp_path / "out"
    given = str(tmp_path / "in" / "deep" / ".." / "deep" / odd.name)          # a path through '..'
    records = seamless_ao.batch([given], output_dir=str(out), jobs=1, uv_policy="new", per_object=True, rays=16,
                                image_size=256, texture_size=256, progress=lambda line: None)
    assert [r.status for r in records] == ["baked"], records
    written = [p for p in out.iterdir() if not p.name.startswith(".seamless_ao")]
    assert [p.name for p in written] == ["touch_x_name__ao.glb"]
    assert written[0].resolve().parent == out.resolve()
    data = glb_json(written[0])
    assert {m["occlusionTexture"].get("texCoord", 0) for m in data["materials"]} == {1}   # beside UVMap
    assert len(data["images"]) == 2


def test_every_format_it_reads_gives_a_glb_with_occlusion(tmp_path):
    """.gltf (with a .bin beside it), .fbx, .ply and .stl: each through its importer, out as .glb."""
    inputs = other_formats(tmp_path / "in")
    out = tmp_path / "out"
    records = seamless_ao.batch([str(tmp_path / "in")], output_dir=str(out), jobs=2, rays=16, image_size=256,
                                texture_size=256, progress=lambda line: None)
    assert sorted(os.path.basename(r.input) for r in records) == sorted(p.name for p in inputs)
    assert all(r.status == "baked" for r in records), [(r.input, r.error) for r in records]
    for record in records:
        data = glb_json(pathlib.Path(record.output))
        assert data["materials"] and all("occlusionTexture" in m for m in data["materials"]), record.input
        assert record.triangles == 970, record          # Suzanne's 968 and the plate's 2, whatever the format


def test_bad_batch_requests_get_a_sentence(tmp_path):
    proc, _ = run_batch(str(tmp_path / "missing"))
    assert proc.returncode == 2 and "seamless_ao: error: no asset to bake" in proc.stderr, proc.stderr
    from seamless_ao.core.errors import SeamlessAOError
    with pytest.raises(SeamlessAOError, match="no asset to bake: .*no such file or folder"):
        seamless_ao.batch([str(tmp_path / "missing")])
    (tmp_path / "notes.txt").write_text("hello")
    with pytest.raises(SeamlessAOError, match="not a file type Seamless AO reads"):
        seamless_ao.batch([str(tmp_path / "notes.txt")])
    with pytest.raises(SeamlessAOError, match="rays"):
        seamless_ao.batch([str(tmp_path)], rays=0)
    with pytest.raises(SeamlessAOError, match="save_image is not available in a batch"):
        seamless_ao.batch([str(tmp_path)], save_image="PNG")


def test_an_asset_over_the_timeout_is_stopped_and_reported(first_run, tmp_path):
    records = seamless_ao.batch([str(first_run["assets"]["obj"])], output_dir=str(tmp_path), jobs=1, timeout=0.2,
                                progress=lambda line: None)
    assert [r.status for r in records] == ["failed"]
    assert records[0].error == "stopped after 0.2 s (--timeout); the asset took longer"
    assert not any(tmp_path.glob("*.glb"))


#: A stand-in worker: writes its half-finished output, then (if told) sleeps, then finishes like a real one.
FAKE_WORKER = """
import json, os, sys, time
job = json.load(open(sys.argv[1]))
output = job["output"]
partial = "{}.part{}{}".format(output, os.getpid(), os.path.splitext(output)[1])
open(partial, "w").write("half")
time.sleep(float(os.environ.get("FAKE_WORKER_SECONDS", "0")))
os.replace(partial, output)
json.dump(dict(input=job["input"], output=output, status="baked"), open(job["record"], "w"))
"""


def fake_batch(tmp_path, monkeypatch, seconds, timeout, poll_every):
    """One asset through the runner with :data:`FAKE_WORKER`, polled every ``poll_every`` seconds."""
    import subprocess as processes
    import sys
    import time
    from seamless_ao.operators.batch import runner
    asset = tmp_path / "chair.obj"
    asset.write_text("v 0 0 0")
    monkeypatch.setenv("FAKE_WORKER_SECONDS", str(seconds))
    monkeypatch.setattr(runner, "worker_command", lambda job_path: [sys.executable, "-c", FAKE_WORKER, job_path])
    started = []
    original = processes.Popen

    def recorded(*args, **kwargs):
        started.append(original(*args, **kwargs))
        return started[-1]
    monkeypatch.setattr(runner.subprocess, "Popen", recorded)
    sleep = time.sleep
    monkeypatch.setattr(runner.time, "sleep", lambda _: sleep(poll_every))
    try:
        records = seamless_ao.batch([str(asset)], jobs=1, timeout=timeout, progress=lambda line: None)
    finally:
        monkeypatch.undo()
    return records, started[0].pid, tmp_path / "chair_ao.glb"


def test_a_worker_that_finished_before_its_deadline_is_not_reported_stopped(tmp_path, monkeypatch):
    """Polled only after its deadline had passed, a worker that had already finished is collected as it
    finished: baked, with its output, and no failure stamp that would stick."""
    records, _, output = fake_batch(tmp_path, monkeypatch, seconds=0.0, timeout=0.3, poll_every=1.5)
    assert [r.status for r in records] == ["baked"] and output.exists()


def test_a_stopped_worker_leaves_nothing_half_written_behind(tmp_path, monkeypatch):
    records, pid, output = fake_batch(tmp_path, monkeypatch, seconds=60.0, timeout=0.8, poll_every=0.05)
    assert [r.status for r in records] == ["failed"] and "--timeout" in records[0].error
    assert not output.exists() and not list(tmp_path.glob("*.part*")), list(tmp_path.iterdir())
    assert str(pid) not in " ".join(p.name for p in tmp_path.iterdir())


def test_jobs_must_be_at_least_one(tmp_path):
    from seamless_ao.core.errors import SeamlessAOError
    for jobs in (0, -2, 1.5):
        with pytest.raises(SeamlessAOError, match="jobs must be a whole number of worker processes, at least 1"):
            seamless_ao.batch([str(tmp_path)], jobs=jobs)
    proc, _ = run_batch(str(tmp_path), "--jobs", "0")
    assert proc.returncode == 2 and "jobs must be a whole number" in proc.stderr, proc.stderr
