"""What a TriangleMesh works out from its corners, and its normals held at the mesh's own corners
(core/mesh/triangle_mesh.py, core/mesh/corner_values.py)."""

import numpy as np
import pytest

from seamless_ao.core.mesh.corner_values import CornerValues
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh


def test_what_the_mesh_works_out_per_use_has_the_same_bits_for_any_subset_and_after_it_let_go():
    """TriangleMesh keeps its unit normals, heights and cross products only as far as it must (normals as read,
    heights not at all, the cross product until the layout lets go): what a pass asks for, for any subset of
    triangles, is what the whole mesh's arrays hold there, bit for bit, and so is the cross product worked out
    again.  float32 normals as read (Blender's) with broken ones included."""
    rng = np.random.default_rng(3)
    positions = rng.normal(0, 1, (60, 3))
    triangles = np.array([rng.choice(60, 3, replace=False) for _ in range(200)])
    triangles[:5, 1] = triangles[:5, 0]                                     # degenerate triangles
    read = rng.normal(0, 1, (200, 3, 3)).astype(np.float32)
    read[7, 1], read[9, 2, 0] = 0.0, np.nan
    mesh = TriangleMesh(positions, triangles, np.arange(200), read)
    assert mesh.normals_as_read.dtype == np.float32 and mesh.normals_as_read.shape == (200, 3, 3)
    normals, height, cross = mesh.corner_normals, mesh.corner_height, mesh.triangle_cross.copy()
    assert np.isfinite(normals).all() and np.allclose(np.linalg.norm(normals, axis=2), 1.0)
    assert (height[:5] == 0.0).all() and (height[5:] > 0.0).all()
    subset = rng.permutation(200)[:37]
    assert np.array_equal(mesh.normals_of(subset), normals[subset])
    assert np.array_equal(mesh.corner_height_of(subset), height[subset])
    mesh.let_go_of_cross()
    assert mesh._cross is None and np.array_equal(mesh.triangle_cross, cross)


def test_a_face_per_triangle_in_order_has_the_triangles_normals_as_its_faces_bit_for_bit():
    """The shortcut (faces in triangle order) against the general sum over each face's triangles (the same faces,
    numbered in another order): the same bits, zero and negative-zero components (triangles flat in z) and
    degenerate triangles included."""
    rng = np.random.default_rng(5)
    positions = rng.normal(0, 1, (60, 3))
    positions[:20, 2] = 0.0
    triangles = np.array([rng.choice(60, 3, replace=False) for _ in range(200)])
    triangles[:10] = [rng.choice(20, 3, replace=False) for _ in range(10)]         # flat in z
    triangles[10:15, 1] = triangles[10:15, 0]                                        # degenerate
    normals = np.zeros((200, 3, 3))
    in_order = TriangleMesh(positions, triangles, np.arange(200), normals)
    order = rng.permutation(200)
    shuffled = TriangleMesh(positions, triangles, order, normals)
    assert np.signbit(in_order.triangle_normal[:10, :2]).any()
    assert np.array_equal(in_order.face_normal, shuffled.face_normal[order])
    assert not np.signbit(in_order.face_normal[:10, :2]).any()


def test_normals_held_at_the_mesh_corners_give_what_the_gathered_array_gives():
    """A reader hands the normals at the mesh's own corners and each triangle corner's corner (CornerValues): the
    mesh's normals of any subset, its longest sides and face normals, a mesh put together and numpy's array of it
    are what the gathered (t, 3, 3) array gives, bit for bit; a corner past the values is refused."""
    rng = np.random.default_rng(4)
    positions = rng.normal(0, 1, (60, 3))
    triangles = np.array([rng.choice(60, 3, replace=False) for _ in range(200)])
    at_corners = rng.normal(0, 1, (450, 3)).astype(np.float32)
    at_corners[17] = 0.0                                                   # broken: replaced by the face normal
    corner = rng.integers(0, 450, (200, 3))
    corner[3, 1] = 17
    held = CornerValues(at_corners, corner)
    gathered = at_corners[corner]
    assert held.shape == (200, 3, 3) and held.dtype == np.float32 and len(held) == 200
    assert np.array_equal(np.asarray(held), gathered) and np.array_equal(held[5:9], gathered[5:9])
    given, plain = (TriangleMesh(positions, triangles, np.arange(200), normals) for normals in (held, gathered))
    subset = rng.permutation(200)[:37]
    assert np.array_equal(given.normals_of(subset), plain.normals_of(subset))
    assert np.array_equal(given.corner_normals, plain.corner_normals)
    assert np.array_equal(given.longest_side, plain.longest_side)
    assert np.array_equal(given.face_normal, plain.face_normal)
    both, _ = TriangleMesh.concatenate([given, plain])
    assert np.array_equal(both.normals_of(np.arange(400)), np.concatenate([plain.corner_normals] * 2))
    corner[0, 0] = 450
    with pytest.raises(ValueError):
        CornerValues(at_corners, corner)
