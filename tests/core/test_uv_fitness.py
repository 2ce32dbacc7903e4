"""Issue 29: whether a UV map can hold the AO (core/export/uv_fitness.py), on maps whose faults are known."""

import numpy as np

from seamless_ao.core.export.uv_fitness import TOLERATED_SHARE, uv_fitness


def grid_map(cells=8, offset=(0.0, 0.0), scale=1.0):
    """A cells x cells grid of quads (two triangles each) filling [0, 1]² (then scaled and moved), unit 3D
    area per quad: UVs (t, 3, 2) and areas (t,)."""
    uv = []
    for i in range(cells):
        for j in range(cells):
            a, b = np.array([i, j]) / cells, np.array([i + 1, j]) / cells
            c, d = np.array([i + 1, j + 1]) / cells, np.array([i, j + 1]) / cells
            uv += [[a, b, c], [a, c, d]]
    return np.array(uv) * scale + offset, np.full(2 * cells * cells, 0.5)


def test_a_clean_unwrap_can_hold_the_ao():
    uv, area = grid_map()
    fitness = uv_fitness(uv, area)
    assert fitness.shared == fitness.outside == fitness.collapsed == fitness.mirrored == 0.0
    assert fitness.can_hold_ao and fitness.problems() == []


def test_stacked_islands_share_uv_space():
    """Two copies of one island on the same UVs (a mirrored half stacked on the other), next to a third
    island of their size: two thirds of the surface share UV space."""
    left, area = grid_map(offset=(0.0, 0.0), scale=0.5)
    right, _ = grid_map(offset=(0.5, 0.0), scale=0.5)
    stacked = left[:, ::-1]                                       # the same place, wound the other way
    fitness = uv_fitness(np.concatenate([left, stacked, right]), np.concatenate([area, area, area]))
    assert abs(fitness.shared - 2.0 / 3.0) < 0.02, fitness
    assert abs(fitness.mirrored - 1.0 / 3.0) < 1e-9
    assert not fitness.can_hold_ao
    assert fitness.problems() == ["67% of the surface shares UV space with other faces"]


def test_tiling_uvs_are_outside_the_square():
    uv, area = grid_map(scale=4.0)                              # a wall textured with a repeated tile
    fitness = uv_fitness(uv, area)
    assert fitness.outside > 0.9 and not fitness.can_hold_ao
    assert "outside the 0-1 square" in fitness.problems()[0]


def test_collapsed_faces_and_mirrored_islands_apart():
    """Faces squashed to a line are a fault; an island mirrored beside another, not stacked, is not."""
    left, area = grid_map(scale=0.5)
    right, _ = grid_map(offset=(1.0, 0.0), scale=(-0.5, 0.5))    # mirrored into [0.5, 1]
    flat = left.copy()
    flat[:, :, 1] = 0.7                                          # a strip of faces collapsed onto one line
    fitness = uv_fitness(np.concatenate([left, right, flat[:10]]), np.concatenate([area, area, area[:10]]))
    triangles = len(left) + len(right) + 10
    assert fitness.shared == 0.0 and abs(fitness.mirrored - len(right) / triangles) < 1e-9
    assert abs(fitness.collapsed - 10 / triangles) < 1e-9
    assert fitness.collapsed > TOLERATED_SHARE and not fitness.can_hold_ao
