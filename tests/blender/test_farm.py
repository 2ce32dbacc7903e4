"""Issue 54: the batch on a real Dask cluster (a ``dask scheduler`` and two ``dask worker`` processes on the
loopback address): the same outputs as a local batch, a worker killed while it holds an asset, a batch stopped
halfway and started again.  Heavy (Blender 5.0 only, where ``make`` installs requirements/farm.txt)."""

import hashlib
import json
import os
import signal
import subprocess
import sys

import bpy
import pytest

from batch_assets import make_asset_folder, stack_blend
from dask_cluster import dask_cluster, wait_for
from marks import heavy
from package import LAUNCHER, seamless_ao

FAST = ("--rays", "16", "--image-size", "256", "--texture-size", "256")
GOOD = ("with_uv.glb", "no_uv.glb", "monkey.obj", "room.blend", "stack.blend")
BAD = ("broken.glb", "edges.obj")


def asset_process():
    from seamless_ao.operators.batch import asset_process
    return asset_process


@pytest.fixture(scope="module")
def assets(tmp_path_factory):
    """The batch test's six assets (two of them bad) and a .blend with a live modifier stack."""
    root = tmp_path_factory.mktemp("farm_assets")
    make_asset_folder(root, root / "ran_code.txt")
    stack_blend(root / "stack.blend")
    return root


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """A Dask scheduler and two workers (one thread each) on 127.0.0.1; yields ``(address, client)``. The
    workers bake with this Python (the bpy module), whatever blender a PATH may hold."""
    with dask_cluster(tmp_path_factory.mktemp("dask"), workers=2,
                      environment={asset_process().BLENDER_VARIABLE: sys.executable}) as running:
        yield running


def batch_command(assets, out, *extra):
    return [sys.executable, str(LAUNCHER), "command", "batch", str(assets), "--output-dir", str(out),
            "--report", str(out.parent / (out.name + ".json")), *FAST, *extra]


def report_of(out):
    report = json.loads((out.parent / (out.name + ".json")).read_text())
    return {os.path.basename(record["input"]): record for record in report["assets"]}


def no_partial_output(out):
    return [p.name for p in out.iterdir() if ".part" in p.name] == []


@heavy
def test_a_cluster_bakes_the_folder_as_a_local_batch_does(assets, cluster, tmp_path):
    from gltf_checks import validate
    address, _ = cluster
    farm, local = tmp_path / "farm", tmp_path / "local"
    proc = subprocess.run(batch_command(assets, farm, "--scheduler", address), capture_output=True, text=True,
                          timeout=900)
    assert proc.returncode == 1, proc.stdout + proc.stderr                 # the two bad assets
    assert "Batch: 5 baked, 0 up to date, 2 failed" in proc.stdout, proc.stdout + proc.stderr
    proc = subprocess.run(batch_command(assets, local, "--jobs", "2"), capture_output=True, text=True, timeout=900)
    assert "Batch: 5 baked, 0 up to date, 2 failed" in proc.stdout, proc.stdout + proc.stderr
    on_farm, here = report_of(farm), report_of(local)
    assert sorted(on_farm) == sorted(GOOD + BAD)
    for name in BAD:
        assert on_farm[name]["status"] == "failed" and on_farm[name]["error"] == here[name]["error"]
    assert on_farm["broken.glb"]["error"].startswith("could not read broken.glb: ")
    for name in GOOD:
        assert on_farm[name]["status"] == "baked", on_farm[name]
    written = sorted(p.name for p in farm.iterdir() if not p.name.startswith("."))
    assert written == sorted(p.name for p in local.iterdir() if not p.name.startswith("."))
    for name in written:
        if name.endswith(".glb"):                  # the same bytes as the local batch's (the bake is seeded)
            # digests, not bytes: pytest works out the diff of two differing MB-long byte strings for hours
            digests = [hashlib.sha256((folder / name).read_bytes()).hexdigest() for folder in (farm, local)]
            assert digests[0] == digests[1], name
    for path, report in validate(sorted(farm.glob("*.glb"))).items():
        assert report["errors"] == 0 and report["warnings"] == 0, (path, report["messages"])
    assert no_partial_output(farm)


@heavy
def test_a_worker_killed_holding_an_asset_costs_nothing(assets, cluster, tmp_path):
    """SIGKILL the worker process that holds an asset: the scheduler gives the asset to a worker again, its
    bake dies with the worker (no second bake writing the same file), every good asset is baked and reported
    once, and nothing half-written is left."""
    address, client = cluster
    out = tmp_path / "out"
    batch = subprocess.Popen(batch_command(assets, out, "--scheduler", address), stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    holding = {}

    def someone_holds_an_asset():
        holding.update({worker: keys for worker, keys in client.processing().items()
                        if any(key.startswith("seamless-ao-") for key in keys)})
        return bool(holding)

    wait_for(someone_holds_an_asset, "a worker to hold an asset")
    worker = sorted(holding)[0]
    killed_key = next(key for key in holding[worker] if key.startswith("seamless-ao-"))
    import psutil
    process = psutil.Process(client.run(os.getpid, workers=[worker])[worker])
    wait_for(process.children, "the worker to start its bake's process")
    bakes = process.children(recursive=True)
    process.kill()
    # the bake dies with its worker at once (a bake takes seconds): no second bake of the asset goes on
    wait_for(lambda: not any(bake.is_running() and bake.status() != psutil.STATUS_ZOMBIE for bake in bakes),
             "the killed worker's bake to end", patience=1.0)
    stdout, stderr = batch.communicate(timeout=900)
    assert batch.returncode == 1, stdout + stderr
    records = report_of(out)
    assert sorted(records) == sorted(GOOD + BAD)
    assert len(json.loads((out.parent / "out.json").read_text())["assets"]) == len(GOOD + BAD)   # reported once
    killed_asset = next(name for name in GOOD + BAD if killed_key.endswith("-" + name))
    for name in GOOD:
        assert records[name]["status"] == "baked", (name, records[name])
    assert records[killed_asset]["status"] == ("failed" if killed_asset in BAD else "baked")
    assert "Batch: 5 baked, 0 up to date, 2 failed" in stdout
    assert no_partial_output(out)


@heavy
def test_a_batch_stopped_halfway_bakes_only_what_is_missing_when_started_again(assets, cluster, tmp_path):
    address, client = cluster
    out = tmp_path / "out"
    batch = subprocess.Popen(batch_command(assets, out, "--scheduler", address), stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
    stamps = seamless_ao.core.other_processes.batch_plan.read_stamps
    wait_for(lambda: len(stamps(out)) >= 2, "two assets finished")
    batch.send_signal(signal.SIGKILL)                 # stopped as a crash or a pulled plug stops it
    batch.wait(30)
    done_before = {os.path.basename(stamp["input"]) for stamp in stamps(out).values()}
    assert 2 <= len(done_before) < len(GOOD + BAD), done_before
    # what the stopped batch's tasks still run finishes or is cancelled before the second run
    wait_for(lambda: not any(key.startswith("seamless-ao-") for keys in client.processing().values()
                             for key in keys), "the first run's tasks to end")
    proc = subprocess.run(batch_command(assets, out, "--scheduler", address), capture_output=True, text=True,
                          timeout=900)
    records = report_of(out)
    assert sorted(records) == sorted(GOOD + BAD)                    # the report covers every asset
    skipped = {name for name, record in records.items() if record["skipped"]}
    assert skipped == done_before, (skipped, done_before, proc.stderr)
    for name in set(GOOD) - done_before:
        assert records[name]["status"] == "baked" and not records[name]["skipped"], records[name]
    assert "Batch: {} baked".format(len(set(GOOD) - done_before)) in proc.stdout, proc.stdout
    assert no_partial_output(out)


def test_a_task_bakes_its_asset_in_a_blender_process_of_its_own(assets, tmp_path, monkeypatch):
    """What a Dask worker runs, without Dask: under Blender (the real binary, in test_suite_in_blender) the task
    starts ``blender --background --factory-startup --disable-autoexec --python-exit-code 1``, under the bpy
    module this Python; either bakes the asset and returns its record."""
    from seamless_ao.core.settings import BakeSettings, GltfSettings
    from seamless_ao.operators.batch.runner import worker_options
    tasks = asset_process()
    binary = bpy.app.binary_path
    binary = binary if binary and not os.path.basename(binary).startswith("python") else sys.executable
    monkeypatch.setenv(tasks.BLENDER_VARIABLE, binary)
    # where Blender's own Python finds xatlas, as docs/pipelines.md tells a farm to say
    monkeypatch.setenv("SEAMLESS_AO_PATHS", os.pathsep.join(p for p in sys.path if p and os.path.isdir(p)))
    options = worker_options(BakeSettings.from_kwargs(rays=16, image_size=256), GltfSettings(texture_size=256))
    job = dict(options, input=str(assets / "monkey.obj"), output=str(tmp_path / "monkey_ao.glb"))
    record = tasks.bake_in_process(job, str(LAUNCHER.parents[2]))
    assert record["status"] == "baked", record
    assert record["triangles"] > 0 and (tmp_path / "monkey_ao.glb").stat().st_size > 0
    assert tasks.launch_command(binary, LAUNCHER, "worker")[1:6] == (
        ["--background", "--factory-startup", "--disable-autoexec", "--python-exit-code", "1"]
        if binary != sys.executable else [str(LAUNCHER), "worker"])


def test_a_worker_without_the_package_or_blender_fails_its_asset_with_a_sentence(tmp_path, monkeypatch):
    tasks = asset_process()
    job = {"input": str(tmp_path / "a.glb"), "output": str(tmp_path / "a_ao.glb")}
    record = tasks.bake_in_process(job, str(tmp_path / "nowhere"))
    assert record["status"] == "failed" and "has no Seamless AO at" in record["error"]
    assert tasks.PACKAGE_VARIABLE in record["error"]
    monkeypatch.setenv(tasks.BLENDER_VARIABLE, str(tmp_path / "no_blender_here"))
    record = tasks.bake_in_process(job, str(LAUNCHER.parents[2]))
    assert record["status"] == "failed" and "found no Blender" in record["error"], record


def test_a_scheduler_and_jobs_together_are_refused(assets):
    with pytest.raises(seamless_ao.core.errors.SeamlessAOError, match="give --jobs or --scheduler, not both"):
        seamless_ao.batch([str(assets)], jobs=2, scheduler="tcp://127.0.0.1:1", progress=lambda line: None)


def test_a_scheduler_the_batch_cannot_use_is_a_sentence(assets, monkeypatch, tmp_path):
    """Without Dask (Blender 4.2 and 5.2 here): how to install it; with it (5.0): which address did not answer."""
    from seamless_ao.operators.batch import farm
    try:
        import distributed  # noqa: F401
        expected = "could not reach the Dask scheduler at tcp://127.0.0.1:1"
    except ImportError:
        expected = "--scheduler needs Dask, which this Python does not have: install"
    monkeypatch.setattr(farm, "CONNECT_SECONDS", 2)
    with pytest.raises(seamless_ao.core.errors.SeamlessAOError, match=expected):
        seamless_ao.batch([str(assets / "monkey.obj")], output_dir=str(tmp_path), scheduler="tcp://127.0.0.1:1",
                          progress=lambda line: None)


@heavy
def test_the_bake_on_a_worker_gets_the_cores_not_the_nannys_one_thread_limits():
    """A Dask nanny sets OMP/MKL/OpenBLAS to one thread for its worker; the bake's own process drops exactly
    those, and keeps a value the user set otherwise."""
    limited = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="3")
    environment = asset_process().without_worker_limits(limited)
    assert "OMP_NUM_THREADS" not in environment and "OPENBLAS_NUM_THREADS" not in environment
    assert environment["MKL_NUM_THREADS"] == "3"
