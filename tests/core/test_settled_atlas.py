"""core/atlas/settled_atlas.py: an xatlas Atlas let go of only once its worker threads sleep."""

import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from seamless_ao.core.atlas import settled_atlas as settled

linux_only = pytest.mark.skipif(not os.path.isdir(settled.TASKS), reason="threads are listed under /proc (Linux)")


def _process(code):
    """A child Python process running ``code``, and its thread list folder."""
    child = subprocess.Popen([sys.executable, "-c", code])
    time.sleep(0.3)
    return child, "/proc/{}/task".format(child.pid)


@linux_only
def test_a_sleeping_thread_is_asleep_and_a_busy_one_is_not():
    sleeper, sleeper_tasks = _process("import time\ntime.sleep(30)")
    spinner, spinner_tasks = _process("while True:\n    pass")
    try:
        assert settled.thread_asleep(str(sleeper.pid), sleeper_tasks)
        assert not settled.thread_asleep(str(spinner.pid), spinner_tasks)
        assert settled.wait_until_asleep({str(sleeper.pid)}, most=0.05, tasks=sleeper_tasks)
        start = time.perf_counter()
        assert not settled.wait_until_asleep({str(spinner.pid)}, most=0.05, tasks=spinner_tasks)
        assert 0.05 <= time.perf_counter() - start < 2.0
    finally:
        sleeper.kill()
        spinner.kill()
    sleeper.wait()
    assert settled.thread_asleep(str(sleeper.pid), sleeper_tasks)          # gone: nothing to wait for


@linux_only
def test_the_threads_listed_are_this_process_threads():
    ids = settled.thread_ids()
    assert str(threading.get_native_id()) in ids
    assert settled.thread_ids("/no/such/folder") is None


def test_where_threads_cannot_be_listed_it_waits_a_little():
    start = time.perf_counter()
    assert settled.wait_until_asleep(None) is False
    assert time.perf_counter() - start >= settled.UNLISTED_WAIT


@linux_only
def test_leaving_the_block_waits_for_the_threads_the_atlas_started(monkeypatch):
    waited = []
    real = settled.wait_until_asleep
    monkeypatch.setattr(settled, "wait_until_asleep", lambda threads, **kw: waited.append(threads) or real(threads))
    before = settled.thread_ids()
    with settled.settled_atlas() as atlas:
        started = settled.thread_ids() - before
        vertices = np.array([[0, 0], [4, 0], [0, 4]], dtype=np.float32)
        atlas.add_uv_mesh(vertices, np.array([[0, 1, 2]], dtype=np.uint32), np.zeros((1, 1), dtype=np.uint32))
        atlas.generate()
        assert not waited
    assert waited == [started] and started                     # xatlas starts a worker per core but one
    assert all(settled.thread_asleep(thread) for thread in started)
    assert atlas.atlas_count == 1


@linux_only
def test_an_atlas_whose_workers_stay_awake_is_held_until_they_sleep(monkeypatch):
    """Letting go of an atlas whose worker is awake could hang for good: it is held, and let go of by the next
    atlas once its workers sleep."""
    assert settled.release_held() == 0
    real = settled.wait_until_asleep
    monkeypatch.setattr(settled, "wait_until_asleep", lambda threads, **kw: False)       # never asleep in time
    before = settled.thread_ids()
    with settled.settled_atlas() as atlas:
        started = settled.thread_ids() - before
        atlas.generate()
    assert [(held, threads) for held, threads in settled.HELD] == [(atlas, started)]
    del atlas
    assert settled.release_held() == 1                    # still "awake": still held
    monkeypatch.setattr(settled, "wait_until_asleep", real)
    with settled.settled_atlas():                         # the next atlas lets go of it first
        assert settled.HELD == []
    assert all(settled.thread_asleep(thread) for thread in started)    # its worker ended with it, or sleeps
