"""Issue 51: per baked face, the affine map from position to UV that the viewport's surface reads through."""

import numpy as np

from package import seamless_ao  # noqa: F401  (imports the add-on as ``seamless_ao``)

from seamless_ao.core.viewport_uv import face_uv_maps


def quads_and_triangles(rng, faces=40):
    """Faces of 3 or 4 corners, each on a random plane, each with a random chart axis and affine UVs of the
    two coordinates that axis keeps; returns the inputs and the per-face truth."""
    positions, corner_vert, loop_start, uv, drop, truth = [], [], [], [[], [], []], [[], [], []], []
    for face in range(faces):
        size = 3 + face % 2
        origin, u, v = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        points = origin + rng.random((size, 1)) * u + rng.random((size, 1)) * v
        loop_start.append(len(corner_vert))
        corner_vert.extend(range(len(positions), len(positions) + size))
        positions.extend(points)
        maps = []
        for layer in range(3):
            axis = int(rng.integers(3))
            kept = [c for c in range(3) if c != axis]
            matrix, shift = rng.normal(size=(2, 2)), rng.normal(size=2)
            uv[layer].extend(points[:, kept] @ matrix.T + shift)
            drop[layer].extend([axis] * size)
            maps.append((axis, kept, matrix, shift))
        truth.append(maps)
    return (np.array(positions), np.array(corner_vert), np.array(loop_start), np.array(uv), np.array(drop)), truth


def test_each_face_gets_its_charts_map_back():
    rng = np.random.default_rng(3)
    (positions, corner_vert, loop_start, uv, drop), truth = quads_and_triangles(rng)
    linear, offset = face_uv_maps(positions, corner_vert, loop_start, uv, drop)
    assert linear.shape == (3, len(loop_start), 2, 3) and offset.shape == (3, len(loop_start), 2)
    face_of_corner = np.repeat(np.arange(len(loop_start)), np.diff(np.append(loop_start, len(corner_vert))))
    for layer in range(3):
        shown = np.einsum("krc,kc->kr", linear[layer][face_of_corner], positions[corner_vert])
        np.testing.assert_allclose(shown + offset[layer][face_of_corner], uv[layer], atol=1e-4)
    for face, maps in enumerate(truth):
        for layer, (axis, kept, matrix, shift) in enumerate(maps):
            assert np.all(linear[layer, face, :, axis] == 0)
            np.testing.assert_allclose(linear[layer, face][:, kept], matrix, rtol=1e-2, atol=1e-2)
    # off the face, along the dropped axis, the UV stays: the chart projects that way
    point = positions[corner_vert[loop_start[5]]] + np.eye(3)[truth[5][0][0]] * 0.3
    at_corner = linear[0, 5] @ positions[corner_vert[loop_start[5]]] + offset[0, 5]
    np.testing.assert_allclose(linear[0, 5] @ point + offset[0, 5], at_corner, rtol=1e-5, atol=1e-5)


def test_a_face_edge_on_to_its_chart_gets_a_flat_finite_map():
    positions = np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]])
    uv = np.tile(np.array([[0.2, 0.3], [0.4, 0.3], [0.4, 0.5], [0.2, 0.5]]), (3, 1, 1))
    drop = np.array([[1] * 4, [1] * 4, [1] * 4])        # y dropped: the face (x = 0) projects to a line
    linear, offset = face_uv_maps(positions, np.arange(4), np.array([0]), uv, drop)
    assert np.isfinite(linear).all() and np.isfinite(offset).all()
    shown = np.einsum("rc,kc->kr", linear[0, 0], positions) + offset[0, 0]
    assert np.abs(shown - uv[0]).max() <= 0.11
