"""Memory freed in the middle of the heap goes back to the system when asked, and a big bake's stays in it for
its next arrays (core/freed_memory.py)."""

import ctypes
import platform
import sys

import numpy as np
import pytest

from process_memory import resident_mb
from seamless_ao.core.freed_memory import GIVE_BACK_FROM_TRIANGLES, freed_memory_held, give_back_freed_memory

GLIBC = sys.platform.startswith("linux") and platform.libc_ver()[0] == "glibc"


@pytest.mark.skipif(not GLIBC, reason="malloc_trim is glibc's")
def test_pages_freed_under_a_block_still_in_use_leave_the_process_in_a_big_bake_only():
    libc = ctypes.CDLL(None)
    libc.malloc.restype = ctypes.c_void_p
    libc.malloc.argtypes = [ctypes.c_size_t]
    libc.free.argtypes = [ctypes.c_void_p]
    block, count = 64 * 1024, 3200                   # below the mmap threshold: heap blocks, 200 MB
    blocks = [libc.malloc(block) for _ in range(count)]
    for address in blocks:
        ctypes.memset(address, 1, block)             # resident
    for address in blocks[:-1]:
        libc.free(address)                           # the last one keeps the heap's top where it is
    before = resident_mb()
    assert not give_back_freed_memory(GIVE_BACK_FROM_TRIANGLES - 1)    # a small bake keeps its heap
    assert resident_mb() > before - 20
    assert give_back_freed_memory(GIVE_BACK_FROM_TRIANGLES)
    after = resident_mb()
    libc.free(blocks[-1])
    assert before - after > 150, (before, after)


def test_elsewhere_it_says_it_could_not():
    assert give_back_freed_memory(GIVE_BACK_FROM_TRIANGLES) == GLIBC


BIG_BLOCK = 96 << 20    # beyond glibc's largest sliding mmap threshold: outside a hold, a mapping of its own


@pytest.mark.skipif(not GLIBC, reason="mallopt is glibc's")
def test_a_big_bake_holds_what_it_frees_for_its_next_arrays_and_a_small_one_does_not():
    with freed_memory_held(GIVE_BACK_FROM_TRIANGLES) as held:
        assert held
        with freed_memory_held(GIVE_BACK_FROM_TRIANGLES):        # a pipeline's hold within its session's
            np.ones(BIG_BLOCK, dtype=np.uint8)
        resident = resident_mb()
        block = np.ones(BIG_BLOCK, dtype=np.uint8)               # the same pages again
        assert resident_mb() - resident < 16
        del block
        assert resident_mb() > resident - 16                     # freed, and still held
    with freed_memory_held(GIVE_BACK_FROM_TRIANGLES - 1) as held:
        assert not held
        block = np.ones(BIG_BLOCK, dtype=np.uint8)
        resident = resident_mb()
        del block
        assert resident_mb() < resident - 80                     # freed, and gone back to the system
