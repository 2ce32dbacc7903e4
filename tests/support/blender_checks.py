"""Reading back what a bake wrote into Blender data, for tests and the benchmark."""

import numpy as np

from seamless_ao.core.image.shown import blended_ao


def image_array(image):
    """(h, w) float32: the R channel of a Blender image."""
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(height, width, 4)[:, :, 0]


def uv_layer_array(mesh, name):
    """(loops, 2) float64 UVs of one layer."""
    uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    mesh.uv_layers[name].data.foreach_get("uv", uv)
    return uv.reshape(-1, 2).astype(np.float64)


def mesh_snapshot(mesh):
    """Bytes of everything a bake could touch on a mesh: geometry, UV layers, active flags, materials."""
    parts = []
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    parts.append(co.tobytes())
    for layer in mesh.uv_layers:
        parts.append(layer.name.encode() + bytes([layer.active, layer.active_render]))
        parts.append(uv_layer_array(mesh, layer.name).tobytes())
    parts.append(",".join(m.name if m else "-" for m in mesh.materials).encode())
    return b"|".join(parts)


def material_snapshot(material):
    """A comparable description of a material's node tree: nodes, links and Base Color values."""
    from seamless_ao.shaders.material import uses_nodes
    if material is None or material.node_tree is None:
        return (material.name if material else None, uses_nodes(material) if material else None)
    tree = material.node_tree
    nodes = sorted((n.name, n.bl_idname) for n in tree.nodes)
    links = sorted((l.from_node.name, l.from_socket.identifier, l.to_node.name, l.to_socket.identifier)
                   for l in tree.links)
    values = sorted((n.name, tuple(round(v, 6) for v in n.inputs["Base Color"].default_value))
                    for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    keys = sorted(material.keys())
    return (material.name, uses_nodes(material), tuple(nodes), tuple(links), tuple(values), tuple(keys))


def shown_seamless(ob, image, triangle_loops, triangle, bary, normals, strength=1.0, interreflection=0.0):
    """What the Seamless AO node group shows at surface points given as (loop triangle, barycentrics),
    with their shading ``normals`` (k, 3) and the node's Strength and Interreflection; the UVs are read
    back from the mesh."""
    loops = triangle_loops[triangle]                                    # (k, 3)
    layer_uv = np.stack([np.einsum("kc,kcd->kd", bary, uv_layer_array(ob.data, name)[loops])
                         for name in ("AO_X", "AO_Y", "AO_Z")], axis=1)
    return blended_ao(image_array(image), layer_uv, normals, strength, interreflection)


def shown_ao(ob, image, triangle_loops, triangle, bary, corner_normals, strength=1.0, interreflection=0.0):
    """:func:`shown_seamless` with the normals interpolated from ``corner_normals`` (t, 3, 3)."""
    normals = np.einsum("kc,kcd->kd", bary, corner_normals[triangle])
    return shown_seamless(ob, image, triangle_loops, triangle, bary, normals, strength, interreflection)


def surface_under_pixels(ob, mesh, camera, size, subsamples=3):
    """Which surface points of ``ob`` each pixel of a ``size`` x ``size`` render sees.

    Each pixel is sampled on a ``subsamples`` x ``subsamples`` grid (a box
    filter one pixel wide, as the render is set up); pixels where any sample
    misses the object (silhouettes) are left out.

    Parameters
    ----------
    mesh : TriangleMesh of ``ob`` (object space)

    Returns
    -------
    triangles : (k, s) int, bary : (k, s, 3), pixels : (k, 2) (row from the bottom, column)
    """
    import bpy
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree
    from mathutils.geometry import barycentric_transform

    world = np.array(ob.matrix_world)
    positions = mesh.positions @ world[:3, :3].T + world[:3, 3]
    tree = BVHTree.FromPolygons(positions.tolist(), mesh.triangles.tolist(), all_triangles=True)
    frame = camera.data.view_frame(scene=bpy.context.scene)     # top-right, bottom-right, bottom-left, top-left
    origin = camera.matrix_world.translation
    unit = (Vector((1, 0, 0)), Vector((0, 1, 0)), Vector((0, 0, 1)))
    offsets = (np.arange(subsamples) + 0.5) / subsamples
    triangles, barys, pixels = [], [], []
    for row in range(size):
        for col in range(size):
            hits = []
            for dv in offsets:
                for du in offsets:
                    u, v = (col + du) / size, (row + dv) / size
                    local = frame[2] + (frame[1] - frame[2]) * u + (frame[3] - frame[2]) * v
                    direction = (camera.matrix_world @ local - origin).normalized()
                    hit, _, index, _ = tree.ray_cast(origin, direction)
                    if hit is None:
                        break
                    corners = [Vector(c) for c in positions[mesh.triangles[index]]]
                    hits.append((index, np.array(barycentric_transform(hit, *corners, *unit))))
            if len(hits) == subsamples**2:
                triangles.append([h[0] for h in hits])
                barys.append([h[1] for h in hits])
                pixels.append((row, col))
    return np.array(triangles), np.array(barys), np.array(pixels)


def eevee_engine():
    """The EEVEE engine's identifier in this Blender (``BLENDER_EEVEE_NEXT`` in 4.2-4.4)."""
    import bpy
    engines = [item.identifier for item in bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items]
    return "BLENDER_EEVEE_NEXT" if "BLENDER_EEVEE_NEXT" in engines else "BLENDER_EEVEE"


def render_emission(ob, size=48, engine="CYCLES"):
    """Render of ``ob`` with its materials switched to AO-only emission; the camera and (h, w) linear values.

    Cycles: 64 samples, 1-pixel box filter, no denoising.  EEVEE: 64 samples
    and the narrowest pixel filter.  Black world, Standard view transform,
    written as OpenEXR so nothing is tone-mapped or quantised.
    """
    import os

    import bpy
    from package import seamless_ao
    scene = bpy.context.scene
    scene.render.engine = engine
    if engine == "CYCLES":
        scene.cycles.device = "CPU"
        scene.cycles.samples = 64
        scene.cycles.use_denoising = False
        scene.cycles.pixel_filter_type = "BOX"            # each pixel averages itself, nothing else
        scene.cycles.filter_width = 1.0
    else:
        scene.eevee.taa_render_samples = 64
        scene.render.filter_size = 0.0
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.0, -4.0, 0.3)
    camera.rotation_euler = (np.radians(88.0), 0.0, 0.0)
    scene.camera = camera
    scene.world = bpy.data.worlds.new("Black")
    scene.world.color = (0, 0, 0)
    seamless_ao.set_preview([ob], True)
    path = os.path.join(bpy.app.tempdir, "render.exr")
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    return camera, image_array(image)


def rendered_and_blended(ob, engine="CYCLES", size=48, strength=1.0, interreflection=0.0):
    """What a render of a fresh bake shows, and what the blend says it should, at the same pixels.

    ``ob`` is turned so its object space differs from world space, baked
    (16 rays, 256²), its materials' ``Seamless AO`` nodes given ``strength``
    and ``interreflection``, and rendered AO-only by ``engine``.  Returns (k,)
    pixel values and (k,) blends averaged over each pixel's 3x3 surface points.
    """
    import bpy
    from package import seamless_ao
    from seamless_ao.operators.adapters.mesh_data import read_triangles
    from seamless_ao.core.keys import BLEND
    ob.rotation_euler = (0.3, 0.2, 0.5)
    bpy.context.view_layer.update()
    report = seamless_ao.bake([ob], rays=16, image_size=256)
    for slot in ob.material_slots:
        node = slot.material.node_tree.nodes[BLEND]
        node.inputs["Strength"].default_value = strength
        node.inputs["Interreflection"].default_value = interreflection
    camera, rendered = render_emission(ob, size=size, engine=engine)
    mesh, loops = read_triangles(ob.data)
    triangles, barys, pixels = surface_under_pixels(ob, mesh, camera, size)
    samples = triangles.shape[1]
    expected = shown_ao(ob, bpy.data.images[report.image], loops, triangles.ravel(), barys.reshape(-1, 3),
                        mesh.corner_normals, strength, interreflection).reshape(-1, samples).mean(axis=1)
    return rendered[pixels[:, 0], pixels[:, 1]], expected
