"""Issue 17: what a batch decides without Blender: assets, output names, up-to-date checks."""

import os
import pathlib

import pytest

from package import seamless_ao

plan = seamless_ao.core.other_processes.batch_plan


def touch(path, text="x", mtime=None):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    if mtime is not None:
        os.utime(path, ns=(mtime, mtime))
    return path


def test_find_assets_takes_folders_files_and_patterns_once_each(tmp_path):
    a = touch(tmp_path / "set" / "chair.glb")
    b = touch(tmp_path / "set" / "sub" / "table.OBJ")
    touch(tmp_path / "set" / "readme.txt")
    c = touch(tmp_path / "lamp.blend")
    found, problems = plan.find_assets([str(tmp_path / "set"), str(a), str(tmp_path / "*.blend"),
                                        str(tmp_path / "nothing_here")])
    assert found == sorted([a.resolve(), b.resolve(), c.resolve()])
    assert problems == [(str(tmp_path / "nothing_here"),
                         "no such file or folder, and no asset matches it as a pattern")]
    only_glb, _ = plan.find_assets([str(tmp_path / "set")], pattern="*.glb")
    assert only_glb == [a.resolve()]
    _, problems = plan.find_assets([str(tmp_path / "set" / "readme.txt")])
    assert "not a file type Seamless AO reads" in problems[0][1]


@pytest.mark.parametrize("name, stem", [
    ("chair", "chair"), ("../../etc/passwd", "etc_passwd"), ("..", "asset"), ("", "asset"),
    ("-rf $(rm x); ü", "rf_rm_x_"), (".hidden", "hidden"), ("a" * 300, "a" * plan.MAX_NAME)])
def test_safe_stem_keeps_only_plain_characters(name, stem):
    assert plan.safe_stem(name) == stem


def test_outputs_stay_in_the_output_folder_whatever_the_inputs_are_called(tmp_path):
    out = tmp_path / "out"
    inputs = [pathlib.Path("/abs/one/chair.glb"), pathlib.Path("/abs/two/chair.glb"), pathlib.Path("/x/..odd ;name.fbx"),
              pathlib.Path("/x/room.blend"), pathlib.Path("/x/Chair.obj")]
    outputs = plan.plan_outputs(inputs, out)
    names = [outputs[p].name for p in inputs]
    assert all(outputs[p].parent == out.resolve() for p in inputs)
    assert len(set(n.lower() for n in names)) == len(names)                    # no two write one file
    assert names[2] == "odd_name_ao.glb" and names[3] == "room_ao.blend"
    assert names[0].startswith("chair_ao-") and names[0].endswith(".glb")       # collisions get a hash
    beside = plan.plan_outputs([tmp_path / "in" / "chair.glb"])
    assert beside[tmp_path / "in" / "chair.glb"] == (tmp_path / "in" / "chair_ao.glb").resolve()


def test_earlier_outputs_are_not_taken_as_assets(tmp_path):
    chair = tmp_path / "chair.glb"
    assets = [chair, tmp_path / "chair_ao.glb", tmp_path / "rock_ao.glb", tmp_path / "out" / "x_ao.glb"]
    assert plan.drop_outputs(assets, tmp_path / "out") == [chair, tmp_path / "rock_ao.glb"]


def test_what_a_stopped_worker_left_half_written_is_not_taken_as_an_asset(tmp_path):
    """A worker writes ``chair_ao.glb.part<pid>.glb`` and renames it when done; one that was stopped leaves it
    beside the inputs, where the next run must not take it for an asset."""
    chair = tmp_path / "chair.glb"
    left = pathlib.Path(plan.partial_output(tmp_path / "chair_ao.glb", 4321))
    assert left.name == "chair_ao.glb.part4321.glb"
    blend_left = pathlib.Path(plan.partial_output(tmp_path / "room_ao.blend", 7))
    parts_like = tmp_path / "engine.part2.glb"                      # an asset whose own name looks alike
    assert plan.drop_outputs([chair, left, blend_left, parts_like]) == [chair, parts_like]
    touch(left)
    plan.remove_partial_output(tmp_path / "chair_ao.glb", 4321)
    plan.remove_partial_output(tmp_path / "chair_ao.glb", 4321)        # nothing left: no error
    assert not left.exists()


def test_a_result_stands_only_for_the_same_input_and_settings(tmp_path):
    asset = touch(tmp_path / "chair.glb", mtime=10**18)
    output = tmp_path / "chair_ao.glb"
    record = plan.AssetRecord(input=str(asset), output=str(output), status="baked")
    digest = plan.settings_digest({"rays": 16})
    assert plan.previous_result(asset, output, digest) is None                 # never baked
    touch(output, mtime=10**18 + 1)
    plan.write_stamp(output, asset, digest, record)
    assert plan.previous_result(asset, output, digest)["status"] == "baked"
    assert plan.previous_result(asset, output, plan.settings_digest({"rays": 32})) is None
    os.utime(asset, ns=(10**18 + 2, 10**18 + 2))                               # input edited since
    assert plan.previous_result(asset, output, digest) is None
    output.unlink()
    failed = plan.AssetRecord(input=str(asset), output=str(output), error="no faces")
    plan.write_stamp(output, asset, digest, failed)
    assert plan.previous_result(asset, output, digest)["error"] == "no faces"  # the same failure again
    touch(output, mtime=10**18 + 3)
    assert plan.previous_result(asset, output, digest) is None                 # an output written since: bake
    output.unlink()
    touch(asset, text="fixed", mtime=10**18 + 2)
    assert plan.previous_result(asset, output, digest) is None                 # a changed file is tried again


def test_progress_line_counts_and_estimates_time_left():
    record = plan.AssetRecord(input="/a/chair.glb", output="/o/chair_ao.glb", status="baked", seconds={"total": 2.0})
    assert plan.progress_line(1, 4, record, 10.0) == (
        "seamless_ao: [1/4] baked chair.glb -> chair_ao.glb in 2.0 s, about 30 s left")
    assert plan.progress_line(4, 4, record, 10.0).endswith("in 2.0 s")
    assert plan.eta_seconds(0, 4, 1.0) is None
