"""GLB files as a glTF viewer sees them, for the tests: the Khronos validator's verdict, and the occlusion a
viewer would show, read from the file alone (its JSON, its binary chunk and its embedded PNG), never from
the scene that wrote it."""

import json
import os
import pathlib
import struct
import subprocess
import tempfile

import numpy as np

from plain_reference import hidden

ROOT = pathlib.Path(__file__).resolve().parents[2]
VALIDATOR = ROOT / "tests" / "scripts" / "validate_gltf.js"
NODE_MODULES = ROOT / ".node" / "node_modules"
COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def validate(paths):
    """The Khronos glTF validator (npm ``gltf-validator``, installed by make into .node/) on ``paths``:
    ``{path: report}`` with ``errors``, ``warnings`` and ``messages``."""
    assert NODE_MODULES.is_dir(), "the glTF validator is not installed: run make .node/.installed"
    process = subprocess.run(["node", str(VALIDATOR), *map(str, paths)], capture_output=True, text=True,
                             env=dict(os.environ, NODE_PATH=str(NODE_MODULES)), timeout=600)
    assert process.returncode in (0, 1), process.stderr
    reports = [json.loads(line) for line in process.stdout.splitlines() if line.startswith("{")]
    return {report["file"]: report for report in reports}


def read_glb(path):
    """``(json, binary chunk)`` of a .glb file."""
    data = pathlib.Path(path).read_bytes()
    magic, _, _ = struct.unpack_from("<III", data, 0)
    assert magic == 0x46546C67, "not a GLB"
    length, kind = struct.unpack_from("<II", data, 12)
    document = json.loads(data[20:20 + length])
    binary = b""
    offset = 20 + length
    if offset < len(data):
        chunk_length, _ = struct.unpack_from("<II", data, offset)
        binary = data[offset + 8:offset + 8 + chunk_length]
    return document, binary


def accessor(document, binary, index):
    """The values of accessor ``index``: (count, width) array (or (count,) for scalars)."""
    info = document["accessors"][index]
    view = document["bufferViews"][info["bufferView"]]
    kind = np.dtype(COMPONENTS[info["componentType"]])
    width = WIDTH[info["type"]]
    start = view.get("byteOffset", 0) + info.get("byteOffset", 0)
    stride = view.get("byteStride", kind.itemsize * width)
    raw = np.frombuffer(binary, dtype=np.uint8, count=stride * (info["count"] - 1) + kind.itemsize * width,
                        offset=start)
    rows = np.lib.stride_tricks.as_strided(raw, shape=(info["count"], kind.itemsize * width), strides=(stride, 1))
    values = np.ascontiguousarray(rows).view(kind).reshape(info["count"], width)
    if info.get("normalized") and kind != np.float32:
        values = values.astype(np.float64) / np.iinfo(kind).max
    return values[:, 0] if width == 1 else values


def png_header(data):
    """``(width, height, bit depth, channels)`` of PNG bytes."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height, depth, colour = struct.unpack(">IIBB", data[16:26])
    return width, height, depth, {0: 1, 2: 3, 4: 2, 6: 4}[colour]


def decode_png(data):
    """(height, width, 4) float64 in [0, 1]: PNG bytes decoded by Blender's image loader as raw values
    (Non-Color), bottom row first as glTF's v axis runs (v = 0 at the top of the image, so row ``height - 1
    - y`` of the file is Blender's row ``y``)."""
    import bpy
    with tempfile.TemporaryDirectory() as scratch:
        path = pathlib.Path(scratch) / "texture.png"
        path.write_bytes(data)
        image = bpy.data.images.load(str(path))
        try:
            image.colorspace_settings.name = "Non-Color"
            width, height = image.size
            pixels = np.empty(width * height * 4, dtype=np.float32)
            image.pixels.foreach_get(pixels)
        finally:
            bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4).astype(np.float64)


def occlusion_images(document, binary):
    """``{material index: (pixels (h, w, 4) as decode_png gives them, texCoord, strength)}`` of every material
    with an ``occlusionTexture``."""
    found = {}
    for index, material in enumerate(document.get("materials", [])):
        occlusion = material.get("occlusionTexture")
        if occlusion is None:
            continue
        image = document["images"][document["textures"][occlusion["index"]]["source"]]
        view = document["bufferViews"][image["bufferView"]]
        data = binary[view.get("byteOffset", 0):view.get("byteOffset", 0) + view["byteLength"]]
        found[index] = (decode_png(data), occlusion.get("texCoord", 0), occlusion.get("strength", 1.0), data)
    return found


def sample(pixels, channel, uv):
    """Bilinear lookup of one channel at glTF UVs (k, 2): u right, v down from the image's top, texel centres
    at half-integers, clamped at the border (as a viewer's linear sampler with clamp-to-edge)."""
    height, width = pixels.shape[:2]
    x = np.clip(uv[:, 0] * width - 0.5, 0.0, width - 1.0)
    y = np.clip((1.0 - uv[:, 1]) * height - 0.5, 0.0, height - 1.0)     # Blender's rows run bottom up
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    x1, y1 = np.minimum(x0 + 1, width - 1), np.minimum(y0 + 1, height - 1)
    fx, fy = x - x0, y - y0
    value = pixels[:, :, channel]
    return ((1 - fx) * (1 - fy) * value[y0, x0] + fx * (1 - fy) * value[y0, x1]
            + (1 - fx) * fy * value[y1, x0] + fx * fy * value[y1, x1])


def shown_occlusion(path, count=1500, seed=7):
    """What a glTF viewer shows as occlusion (the R channel of each material's occlusion texture through its
    texCoord, with its strength) at random visible points of every primitive, read from the file alone (points
    nobody can see, such as a box's bottom on the floor, are left out, as in every accuracy figure).

    Returns world positions (k, 3), shading normals (k, 3) (the file's NORMAL, interpolated), geometric
    normals (k, 3), the occlusion (k,), and the whole scene's world triangles ``(positions (v, 3), triangles
    (t, 3))`` for a reference.
    """
    document, binary = read_glb(path)
    rng = np.random.default_rng(seed)
    textures = occlusion_images(document, binary)
    corners, triangle_owner, uv_sets, shown_parts, normal_sets, world_index = [], [], [], [], [], []
    world_positions, world_triangles = [], []
    for node in document.get("nodes", []):
        if "mesh" not in node:
            continue
        matrix = _node_matrix(node)
        for primitive in document["meshes"][node["mesh"]]["primitives"]:
            positions = accessor(document, binary, primitive["attributes"]["POSITION"]).astype(np.float64)
            positions = positions @ matrix[:3, :3].T + matrix[:3, 3]
            indices = accessor(document, binary, primitive["indices"]).reshape(-1, 3).astype(np.int64)
            first = sum(len(t) for t in world_triangles)
            world_triangles.append(indices + sum(len(p) for p in world_positions))
            world_positions.append(positions)
            material = primitive.get("material")
            if material not in textures:
                continue
            pixels, texcoord, strength, _ = textures[material]
            uv = accessor(document, binary, primitive["attributes"]["TEXCOORD_{}".format(texcoord)]).astype(float)
            normals = accessor(document, binary, primitive["attributes"]["NORMAL"]).astype(np.float64)
            corners.append(positions[indices])
            world_index.append(first + np.arange(len(indices)))
            normal_sets.append((normals @ np.linalg.inv(matrix[:3, :3]))[indices])
            uv_sets.append(uv[indices])
            shown_parts.append((pixels, strength))
            triangle_owner.append(np.full(len(indices), len(shown_parts) - 1))
    corners, uvs, corner_normals = np.concatenate(corners), np.concatenate(uv_sets), np.concatenate(normal_sets)
    owner, world_index = np.concatenate(triangle_owner), np.concatenate(world_index)
    scene = (np.concatenate(world_positions), np.concatenate(world_triangles))
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    picked = rng.choice(len(area), size=2 * count, p=area / area.sum())
    r1, r2 = rng.random(2 * count), rng.random(2 * count)
    s = np.sqrt(r1)
    bary = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)
    points = np.einsum("kc,kcd->kd", bary, corners[picked])
    seen = np.flatnonzero(~hidden(scene[0], scene[1], world_index[picked], points))[:count]
    picked, bary, points = picked[seen], bary[seen], points[seen]
    count = len(picked)
    normal = np.cross(corners[picked, 1] - corners[picked, 0], corners[picked, 2] - corners[picked, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    point_uv = np.einsum("kc,kcd->kd", bary, uvs[picked])
    shading = np.einsum("kc,kcd->kd", bary, corner_normals[picked])
    shading /= np.linalg.norm(shading, axis=1, keepdims=True)
    shown = np.empty(count)
    for part, (pixels, strength) in enumerate(shown_parts):
        mine = owner[picked] == part
        shown[mine] = 1.0 + strength * (sample(pixels, 0, point_uv[mine]) - 1.0)
    return points, shading, normal, shown, scene


def _node_matrix(node):
    """A node's local matrix (4, 4); the test assets keep every mesh node at the root."""
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    from mathutils import Matrix, Quaternion, Vector
    rotation = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    matrix = Matrix.LocRotScale(Vector(node.get("translation", [0.0, 0.0, 0.0])),
                                Quaternion((rotation[3], rotation[0], rotation[1], rotation[2])),
                                Vector(node.get("scale", [1.0, 1.0, 1.0])))
    return np.array(matrix, dtype=np.float64)
