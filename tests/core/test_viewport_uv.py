"""Issue 51: per baked face, the affine map from position to UV that the viewport's surface reads through."""

import numpy as np

from package import seamless_ao  # noqa: F401  (imports the add-on as ``seamless_ao``)

from seamless_ao.core.atlas.viewport_uv import face_uv_maps, stands_off, surface_uv


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


def two_charts_side_by_side():
    """A baked strip in the plane z = 0: square A (x in [0, 1]) and square B (x in [1, 2]), two triangles
    each, each square in its own chart (x, y projected, far apart in the image); returns the baked arrays
    and each chart's map."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]], dtype=np.float64)
    triangles = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]])
    maps = {"A": lambda p: 0.1 + 0.2 * p[..., :2], "B": lambda p: np.array([0.6, 0.1]) + 0.2 * (p[..., :2] - [1, 0])}
    uv = np.concatenate([maps["A"](positions[triangles[:2]]), maps["B"](positions[triangles[2:]])])  # (4, 3, 2)
    return (positions, triangles), np.tile(uv, (3, 1, 1, 1)), np.full((4, 3), 2), maps


def test_a_face_within_one_chart_reads_that_chart_at_its_corners():
    baked, uv, drop, maps = two_charts_side_by_side()
    shown = (np.array([[0.2, 0.2, 0.05], [0.8, 0.2, 0.05], [0.8, 0.8, 0.05], [0.2, 0.8, 0.05]]), np.arange(4),
             np.array([0]))
    out = surface_uv(baked, uv, drop, shown, (256, 256))
    assert out.shape == (3, 4, 2) and out.dtype == np.float32
    for layer in range(3):
        np.testing.assert_allclose(out[layer], maps["A"](shown[0]), atol=1e-6)


def test_a_face_across_two_charts_reads_one_and_its_edge_past_it():
    """Corners held by the chart of most corners read it; the corner past its edge reads the edge (x = 1)
    instead of texels of the image that belong to another chart or to none."""
    baked, uv, drop, maps = two_charts_side_by_side()
    shown_positions = np.array([[0.3, 0.2, 0.0], [0.6, 0.2, 0.0], [1.7, 0.5, 0.0], [0.3, 0.8, 0.0]])
    shown = (shown_positions, np.arange(4), np.array([0]))
    out = surface_uv(baked, uv, drop, shown, (256, 256))
    held = [0, 1, 3]
    np.testing.assert_allclose(out[0, held], maps["A"](shown_positions[held]), atol=1e-6)
    inside = shown_positions[held].mean(axis=0)
    # the edge point lies on the segment from the held corners' centre to the far corner, where x = 1
    along = (1.0 - inside[0]) / (shown_positions[2, 0] - inside[0])
    edge = inside + along * (shown_positions[2] - inside)
    np.testing.assert_allclose(out[0, 2], maps["A"](edge), atol=0.2 * 2.0 ** -8 + 1e-6)
    assert np.isfinite(out).all() and (out >= 0).all() and (out <= 1).all()


def test_a_cage_stands_off_the_surface_it_gives_and_points_on_it_do_not():
    """A unit square at z = 0 as two triangles: its own corners lie on it, a copy lifted by 2% of its
    diagonal stands off it (a Subdivision cage stands off its surface by about 1.26% of Suzanne's)."""
    positions = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    triangles = np.array([[0, 1, 2], [0, 2, 3]])
    assert not stands_off(positions, triangles, positions)
    assert not stands_off(positions, triangles, positions + [0.0, 0.0, 1e-5])
    assert stands_off(positions, triangles, positions + [0.0, 0.0, 0.02 * np.sqrt(2.0)])
