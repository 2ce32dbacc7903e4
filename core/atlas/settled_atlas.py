"""An xatlas ``Atlas`` let go of only once its worker threads sleep: its destructor can otherwise hang forever.

xatlas runs a thread pool per ``Atlas`` (hardware threads less one).  Its
destructor sets each worker's wake-up flag and signals the worker's
condition variable without holding the worker's mutex, then joins it.  A
worker that has just run out of tasks and found the flag unset, but is not
yet waiting, misses that signal and waits for ever; the join waits for the
worker.  On a busy machine that window is wide enough: a fresh-clone test
run hung there, and so do runs of many small packs with other processes
keeping the cores busy (``tests/scripts/xatlas_release_stress.py``, which
says how often).  In Blender the bake, and the window, would freeze for good.

Once a worker sleeps in its wait, it is registered with the condition
variable and the destructor's signal reaches it.  After ``generate`` a worker
sleeps nowhere else: it takes no lock another thread holds, and spins rather
than sleeps on the task queue.  So :func:`settled_atlas` notes which threads
the ``Atlas`` started (Linux lists a process's threads under
``/proc/self/task``), and before the caller lets go of the atlas waits,
briefly, until each one is asleep.  Where threads cannot be listed (Windows,
macOS) it waits :data:`UNLISTED_WAIT` seconds instead, which narrows the
window without closing it.  An atlas whose workers are still awake after
:data:`MOST_WAIT` (preempted on a busy machine) is not let go of then: it is
held (:data:`HELD`) until a later atlas finds its workers asleep.
"""

import contextlib
import os
import time

#: Where Linux lists this process's threads, one folder each, named by thread id.
TASKS = "/proc/self/task"
#: Longest wait (seconds) for the atlas's workers to sleep; they do within microseconds once ``generate`` returns.
MOST_WAIT = 0.5
#: Seconds between looks at the workers' state.
POLL = 0.0002
#: Seconds waited where the threads cannot be listed.
UNLISTED_WAIT = 0.002

#: Atlases whose workers were still awake when their block was left: (atlas, thread ids), let go of later.
HELD = []


def thread_ids(tasks=TASKS):
    """The ids of this process's threads (a set of str), or None where they cannot be listed."""
    try:
        return set(os.listdir(tasks))
    except OSError:
        return None


def thread_asleep(thread_id, tasks=TASKS):
    """True if the thread sleeps in an interruptible wait (``S``) or has ended; False if it runs, is runnable
    or is in an uninterruptible wait (a page fault in the middle of its work)."""
    try:
        with open(os.path.join(tasks, thread_id, "stat"), encoding="ascii", errors="replace") as handle:
            stat = handle.read()
    except OSError:
        return True                                  # gone
    # "tid (name) S ...": the name may hold spaces and parentheses, the state follows the last ")"
    return stat[stat.rfind(")") + 2:][:1] in ("S", "Z", "X", "")


def wait_until_asleep(thread_set, most=MOST_WAIT, poll=POLL, tasks=TASKS):
    """Wait until every thread of ``thread_set`` sleeps (:func:`thread_asleep`), at most ``most`` seconds;
    ``thread_set`` None (threads not listed here) waits :data:`UNLISTED_WAIT`.  True if they all slept."""
    if thread_set is None:
        time.sleep(UNLISTED_WAIT)
        return False
    deadline = time.perf_counter() + most
    waiting = set(thread_set)
    while True:
        waiting = {thread for thread in waiting if not thread_asleep(thread, tasks)}
        if not waiting:
            return True
        if time.perf_counter() > deadline:
            return False
        time.sleep(poll)


@contextlib.contextmanager
def settled_atlas():
    """``with settled_atlas() as atlas:`` a new ``xatlas.Atlas``, which may be let go of once the block is left:
    by then its workers sleep where its destructor's signal reaches them (see the module)."""
    import xatlas  # bundled wheel; imported here, as in .packing, so the rest of core works without it

    release_held()
    before = thread_ids()
    atlas = xatlas.Atlas()
    after = thread_ids()
    workers = after - before if before is not None and after is not None else None
    try:
        yield atlas
    finally:
        if not wait_until_asleep(workers) and workers is not None:
            # a worker still awake after MOST_WAIT (preempted on a machine busy with other work, say): letting
            # go now could hang for good, so the atlas is held and let go of once its workers sleep
            HELD.append((atlas, workers))


def release_held(most=MOST_WAIT):
    """Let go of each held atlas whose workers sleep now (waiting at most ``most`` seconds for each); returns
    how many are still held."""
    still = []
    for atlas, workers in HELD:
        if not wait_until_asleep(workers, most=most):
            still.append((atlas, workers))
    HELD[:] = still                                    # the others are let go of here
    return len(still)
