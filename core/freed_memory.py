"""Memory a bake has freed: held for the bake's next stage, and handed back before a step that needs much of
its own.

glibc's allocator keeps what a process frees in its heap for later use, and
a heap freed in the middle stays resident.  A bake frees a lot between its
stages: the layout's temporaries, the Geometry Nodes caster's ray batches.
The casters' BVHs and Cycles, which bakes the bulk of the rays, take large
blocks of their own, which that free heap cannot hold, so the process holds
both at once.  On the 1M-triangle meshes of ``tests/bench/bench_million.py``
that is 160 to 290 MB of free heap; glibc's ``malloc_trim`` returns it.

Handing pages back has a price: the heap's pages used again later fault back
in, which cost the 70k- to 250k-triangle bakes of ``tests/bench/report.py``
5 to 6% of their time when every bake did it (their free heap, 20 to 200 MB,
says little about the bake: it is what earlier bakes in the process left).
So only bakes of at least :data:`GIVE_BACK_FROM_TRIANGLES` triangles, whose
peaks it is about, give memory back, and before the rays only where Cycles
bakes the bulk (``core/pipeline.py``): a bake the Geometry Nodes caster
casts alone (as Automatic does at 4 rays or fewer) has no Cycles scene to
make room for, and its next bake would only fault the pages back in.

The other way round, within a big bake's own stages glibc hands back too
much: every block of more than its mmap threshold (32 MB at most, and a
million triangles' arrays are 8 to 36 MB) is a mapping of its own, and so
is a heap top left free beyond its trim threshold; each goes back to the
system when freed, and the next stage's arrays fault in fresh, zeroed
pages.  :func:`freed_memory_held` raises both thresholds for a bake's
pipeline and writes, so what one stage frees the next reuses;
:func:`give_back_freed_memory` sets them back first.  On the two 1M-triangle
meshes' cheapest bakes that cut the main thread's system time by 42 and 57%
and the bake by 6 and 10% (``tests/bench/bench_held_memory.py``).

Elsewhere (another C library, Windows, macOS) this does nothing: glibc's
calls are the ones this was measured with (glibc 2.36).
"""

import ctypes
import sys
from contextlib import contextmanager

#: Bakes of at least this many triangles (the meshes baked; before a Cycles bake, its occluders) give freed
#: memory back (a 1M-triangle bake frees 160 to 290 MB between its stages: its peak is what bench_million watches).
GIVE_BACK_FROM_TRIANGLES = 500_000
#: While a bake of at least GIVE_BACK_FROM_TRIANGLES holds its freed memory (:func:`freed_memory_held`), blocks
#: up to this many bytes come from the heap, and a free heap top of up to twice it stays in it.
HELD_BYTES = 1 << 30
#: glibc's own ceiling for the mmap threshold it raises as a process frees big blocks (4 MiB per byte of a
#: ``long``), which a bake's arrays take it to; the trim threshold follows at twice it.  What a held bake
#: leaves them at.
GLIBC_MMAP_THRESHOLD = 32 << 20
#: ``mallopt``'s parameter numbers (glibc's malloc.h).
M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3


def _glibc_call(name, argtypes):
    """glibc's function ``name`` in this process, or None."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        call = getattr(ctypes.CDLL(None), name)      # the C library the process already uses
    except (OSError, AttributeError):                # no dynamic loading, or not glibc (musl has none)
        return None
    call.argtypes, call.restype = argtypes, ctypes.c_int
    return call


_MALLOC_TRIM = _glibc_call("malloc_trim", [ctypes.c_size_t])
_MALLOPT = _glibc_call("mallopt", [ctypes.c_int, ctypes.c_int]) if _MALLOC_TRIM is not None else None


def _set_thresholds(mmap_bytes):
    """glibc's mmap threshold to ``mmap_bytes`` and its trim threshold to twice it."""
    _MALLOPT(M_MMAP_THRESHOLD, mmap_bytes)
    _MALLOPT(M_TRIM_THRESHOLD, 2 * mmap_bytes)


@contextmanager
def freed_memory_held(triangles):
    """Within a bake of ``triangles`` triangles, at least :data:`GIVE_BACK_FROM_TRIANGLES`: what it frees
    stays in the heap for its next arrays (glibc); yields whether it does.  On leaving the outermost hold,
    glibc's thresholds go back to where its own sliding ones end up (:data:`GLIBC_MMAP_THRESHOLD`; so does
    :func:`give_back_freed_memory`), and the heap's free top beyond that goes back at the next free."""
    global _holding
    held = _MALLOPT is not None and triangles >= GIVE_BACK_FROM_TRIANGLES
    if held:
        _holding += 1
        if _holding == 1:
            _set_thresholds(HELD_BYTES)
    try:
        yield held
    finally:
        if held:
            _holding -= 1
            if not _holding:
                _set_thresholds(GLIBC_MMAP_THRESHOLD)


#: How many holds are entered and not yet left (:func:`freed_memory_held`): a bake's session holds around its
#: pipeline's.
_holding = 0


def give_back_freed_memory(triangles):
    """Before a step that allocates much, in a bake of ``triangles`` triangles: return the heap's free
    pages to the system (glibc) where the bake has at least :data:`GIVE_BACK_FROM_TRIANGLES`, and hold no more
    (:func:`freed_memory_held`); True if it did.

    Costs a walk over the heap and, later, page faults for the pages used again: not for a loop."""
    if _MALLOC_TRIM is None or triangles < GIVE_BACK_FROM_TRIANGLES:
        return False
    if _MALLOPT is not None:
        _set_thresholds(GLIBC_MMAP_THRESHOLD)
    _MALLOC_TRIM(0)
    return True
