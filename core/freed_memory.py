"""Memory a bake has freed, handed back to the system before a step that needs much of its own.

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

Elsewhere (another C library, Windows, macOS) this does nothing: glibc's
call is the one this was measured with.
"""

import ctypes
import sys

#: Bakes of at least this many triangles (the meshes baked; before a Cycles bake, its occluders) give freed
#: memory back (a 1M-triangle bake frees 160 to 290 MB between its stages: its peak is what bench_million watches).
GIVE_BACK_FROM_TRIANGLES = 500_000


def _malloc_trim():
    """glibc's ``malloc_trim`` in this process, or None."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        trim = ctypes.CDLL(None).malloc_trim         # the C library the process already uses
    except (OSError, AttributeError):                # no dynamic loading, or not glibc (musl has none)
        return None
    trim.argtypes, trim.restype = [ctypes.c_size_t], ctypes.c_int
    return trim


_MALLOC_TRIM = _malloc_trim()


def give_back_freed_memory(triangles):
    """Before a step that allocates much, in a bake of ``triangles`` triangles: return the heap's free
    pages to the system (glibc) where the bake has at least :data:`GIVE_BACK_FROM_TRIANGLES`; True if it did.

    Costs a walk over the heap and, later, page faults for the pages used again: not for a loop."""
    if _MALLOC_TRIM is None or triangles < GIVE_BACK_FROM_TRIANGLES:
        return False
    _MALLOC_TRIM(0)
    return True
