"""Take the AO out of Blender: a texture on the user's own UV map (glTF-ready), or a colour attribute.

API (also used by the operators and the command line)::

    resample(objects, uv_map=None, size=1024, padding=8, gltf_occlusion=True) -> [image names]
    to_color_attribute(objects, domain="CORNER") -> [attribute names]

Both need a bake (AO_X/Y/Z and the AO image) and evaluate exactly what the
``Seamless AO`` node group shows; no ray is cast.
"""

from dataclasses import dataclass

import bpy
import numpy as np

from ...core.errors import SeamlessAOError
from ...core.export.export_pipeline import BakedSurface, SlotMaterials, color_values, export_packing, resampled_image
from ...core.export.uv_fitness import uv_fitness
from ...core.keys import AO_LAYERS, COLOR_ATTRIBUTE, COLOR_KEY, EXPORT_KEY, GLTF_GROUP, IMAGE_KEY, OURS_KEY
from ...core.settings import ExportSettings
from ...shaders import material as material_nodes
from ...shaders.gltf_nodes import hook_gltf_occlusion
from . import stack
from .mesh_data import EvaluatedCorners, evaluated_mesh, read_triangles, read_uv, render_evaluation
from .writes import store_png_image

DEFAULTS = ExportSettings()


@dataclass
class Baked:
    """What a bake left on an object, read as the object renders: core's :class:`BakedSurface` and what only the
    Blender side needs to write back."""

    surface: BakedSurface
    loops: np.ndarray           # (t, 3) int32: the evaluated mesh's corner of each triangle corner
    target_uv: np.ndarray       # (t, 3, 2) the asked UV map at each triangle corner, or None
    on_base: bool               # the evaluated corners are the base mesh's (else the AO is through the stack)


def _baked_inputs(ob, target=None):
    """:class:`Baked` of a baked object, as it renders; ``target``: a UV map of its own to read too."""
    if ob is None or ob.type != "MESH":
        raise SeamlessAOError("'{}' is not a mesh".format(getattr(ob, "name", ob)))
    image = bpy.data.images.get(ob.get(IMAGE_KEY, ""))
    helper = stack.helper_of(ob)
    holder = helper.data if helper is not None else ob.data
    if image is None or any(name not in holder.uv_layers for name in AO_LAYERS):
        raise SeamlessAOError("'{}' has no Seamless AO bake; bake it first".format(ob.name))
    with render_evaluation([ob]):
        depsgraph = bpy.context.evaluated_depsgraph_get()
        with evaluated_mesh(ob, depsgraph) as evaluated:
            triangle_mesh, loops = read_triangles(evaluated)
            corners = EvaluatedCorners.of(evaluated)
            material_index = np.zeros(len(evaluated.polygons), dtype=np.int32)
            evaluated.polygons.foreach_get("material_index", material_index)
            target_uv = _loop_uv(evaluated, target)[loops] if target else None
    if not corners.same_as(holder):
        raise SeamlessAOError("'{}' no longer has the surface it was baked with (its modifiers changed); bake it "
                              "again first".format(ob.name))
    layer_uv = np.stack([_loop_uv(holder, name)[loops] for name in AO_LAYERS], axis=1)   # (t, 3, 3, 2)
    slot_blend = np.array([material_nodes.blend_inputs(slot.material) for slot in ob.material_slots] or [(1.0, 0.0)])
    triangle_slot = np.clip(material_index[triangle_mesh.triangle_face], 0, len(slot_blend) - 1)
    surface = BakedSurface(image_values(image).astype(np.float64), layer_uv, triangle_mesh.corner_normals,
                           triangle_mesh.triangle_area, triangle_mesh.degenerate, triangle_slot, slot_blend)
    return Baked(surface, loops, target_uv, helper is None)


def image_values(image):
    """(height, width) float32: the red channel of a Blender image (the AO, in an image a bake wrote)."""
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(height, width, 4)[:, :, 0]


def uv_map_fitness(ob, name):
    """:class:`~...core.export.uv_fitness.UVFitness` of ``ob``'s UV map ``name`` as it renders."""
    with render_evaluation([ob]):
        with evaluated_mesh(ob, bpy.context.evaluated_depsgraph_get()) as evaluated:
            mesh, loops = read_triangles(evaluated)
            uv = _loop_uv(evaluated, name)[loops]
    return uv_fitness(uv, mesh.triangle_area)


def slot_materials(ob, target):
    """:class:`~...core.export.export_pipeline.SlotMaterials` of ``ob``'s slots: each one's Roughness and
    Metallic, and the texture channels it reads them from through the UV map ``target`` itself (the resampled
    image's texels then lie where its texels do); a texture read through another map leaves the input's own
    value standing."""
    slots = [getattr(slot, "material", None) for slot in ob.material_slots] or [None]
    default_uv_map = render_active_uv(ob)
    values = np.zeros((len(slots), 2))
    sources, pixels, uses = [], {}, []
    for s, material in enumerate(slots):
        for v, (value, texture) in enumerate(material_nodes.principled_values(material, default_uv_map).values()):
            values[s, v] = value
            if texture is None:
                continue
            image, channel, uv_map = texture
            if uv_map != target or min(image.size) < 1:
                continue
            if image.name not in pixels:
                width, height = image.size
                flat = np.empty(width * height * 4, dtype=np.float32)
                image.pixels.foreach_get(flat)
                pixels[image.name] = flat.reshape(height, width, 4).astype(np.float64)
            if (v, image.name, channel) not in sources:
                sources.append((v, image.name, channel))
            uses.append((s, sources.index((v, image.name, channel))))
    texture_use = np.zeros((len(slots), len(sources)), dtype=bool)
    for s, j in uses:
        texture_use[s, j] = True
    return SlotMaterials(values, texture_use, [(v, pixels[name][:, :, channel]) for v, name, channel in sources])


def _loop_uv(mesh, name):
    return read_uv(mesh, name).astype(np.float64)


def render_active_uv(ob):
    """The name of ``ob``'s render-active UV map (what an Image Texture with no UV Map node reads), or ""."""
    return next((uv.name for uv in ob.data.uv_layers if uv.active_render), "")


def own_uv_map(ob, name=None):
    """The UV map to resample onto: ``name``, else the render-active one, else the active one (not AO_*)."""
    layers = [uv for uv in ob.data.uv_layers if uv.name not in AO_LAYERS]
    if name:
        if name not in ob.data.uv_layers or name in AO_LAYERS:
            raise SeamlessAOError("'{}' has no UV map named '{}' (its UV maps: {})".format(
                ob.name, name, ", ".join(uv.name for uv in layers) or "none"))
        return name
    for uv in layers:
        if uv.active_render:
            return uv.name
    active = ob.data.uv_layers.active
    if active is not None and active.name not in AO_LAYERS:
        return active.name
    if layers:
        return layers[0].name
    raise SeamlessAOError("'{}' has no UV map of its own to resample onto; unwrap it first".format(ob.name))


def resample(objects, uv_map=None, size=DEFAULTS.size, padding=DEFAULTS.padding,
             gltf_occlusion=DEFAULTS.gltf_occlusion, material_strength=DEFAULTS.material_strength,
             packing=DEFAULTS.packing, bit_depth=DEFAULTS.bit_depth, unfit_uv_map=DEFAULTS.unfit_uv_map):
    """Write each object's blended AO into a new image on one of its own UV maps.

    Parameters
    ----------
    objects : list of baked mesh objects
    uv_map : str, optional, defaults to the render-active UV map (never AO_*)
    size : int, width and height of the new image
    padding : int, texels of dilation around every UV island
    gltf_occlusion : bool
        Also wire the image into every material through a "glTF Material
        Output" group's Occlusion input, so Blender's glTF exporter writes it
        as the material's ``occlusionTexture``.
    material_strength : bool
        Apply each material's Strength and Interreflection (the ``Seamless AO``
        node's inputs), so the texture shows what the material shows.
    packing : {"GLTF", "GREY", "ORM", "UNITY_MASK"}
        Which channels carry the AO (:data:`~...core.export.packings.PACKINGS`); ORM
        and the Unity mask map carry each material's roughness and metallic
        too, from its metallic-roughness texture where one is read through
        the same UV map (:func:`slot_materials`).
    bit_depth : {"16", "8"}
        Bits per channel of the image: a PNG packed into the .blend, which
        the glTF exporter embeds as it is.
    unfit_uv_map : bool
        Resample even onto a UV map that cannot hold the AO
        (:func:`~...core.export.uv_fitness.uv_fitness`); by default that is refused
        with what is wrong with it.

    Returns
    -------
    list of image names (``<object>_AO_<uv map>``)
    """
    settings = ExportSettings.from_kwargs(uv_map=uv_map or "", size=size, padding=padding,
                                          gltf_occlusion=gltf_occlusion, material_strength=material_strength,
                                          packing=packing, bit_depth=bit_depth, unfit_uv_map=unfit_uv_map)
    packing = export_packing(settings)
    names = []
    for ob in objects:
        target = own_uv_map(ob, settings.uv_map or None)
        baked = _baked_inputs(ob, target)
        materials = slot_materials(ob, target) if packing.carries_material else None
        png = resampled_image(baked.surface, baked.target_uv, settings, ob.name, target, materials)
        image = store_png_image("{}_AO_{}".format(ob.name, target), png, marks=(OURS_KEY, EXPORT_KEY))
        if settings.gltf_occlusion:
            for material in {s.material for s in ob.material_slots if s.material is not None}:
                hook_gltf_occlusion(material, image, target)
        names.append(image.name)
    return names


def to_color_attribute(objects, domain=DEFAULTS.domain, material_strength=DEFAULTS.material_strength):
    """Write each object's blended AO into a colour attribute ``AO`` (face corners or points).

    Point values average the object's corners at each vertex.
    """
    settings = ExportSettings.from_kwargs(domain=domain, material_strength=material_strength)
    domain = settings.domain
    for ob in objects:
        baked = _baked_inputs(ob)
        if not baked.on_base:
            raise SeamlessAOError(
                "'{}' is baked through its modifier stack (its modifiers change its faces, or its mesh is shared), "
                "so a colour attribute on its mesh cannot hold the AO of the surface that renders; resample the "
                "AO onto a UV map instead".format(ob.name))
        data = ob.data
        vertex = None
        if domain == "POINT":
            vertex = np.empty(len(data.loops), dtype=np.int32)
            data.loops.foreach_get("vertex_index", vertex)
        per_element = color_values(baked.surface, settings, baked.loops, len(data.loops), vertex, len(data.vertices))
        existing = data.color_attributes.get(COLOR_ATTRIBUTE)
        if existing is not None and (existing.domain != domain or existing.data_type != "FLOAT_COLOR"):
            data.color_attributes.remove(existing)
            existing = None
        if existing is None and COLOR_ATTRIBUTE in data.attributes:
            raise SeamlessAOError("'{}' already has an attribute named '{}' that is not a colour; rename it "
                                  "first".format(ob.name, COLOR_ATTRIBUTE))
        attribute = existing or data.color_attributes.new(COLOR_ATTRIBUTE, "FLOAT_COLOR", domain)
        ob[COLOR_KEY] = True
        colours = np.repeat(per_element.astype(np.float32)[:, None], 4, axis=1)
        colours[:, 3] = 1.0
        attribute.data.foreach_set("color", colours.ravel())
    return [COLOR_ATTRIBUTE for _ in objects]


def clear_exports(ob):
    """Remove the colour attribute and unused images and glTF group the exports made for ``ob``."""
    touched = False
    if ob.get(COLOR_KEY):
        attribute = ob.data.color_attributes.get(COLOR_ATTRIBUTE)
        if attribute is not None:
            ob.data.color_attributes.remove(attribute)
        del ob[COLOR_KEY]
        touched = True
    for image in [i for i in bpy.data.images if i.get(EXPORT_KEY) and i.name.startswith(ob.name + "_AO_")]:
        if image.users == 0:
            bpy.data.images.remove(image)
            touched = True
    group = bpy.data.node_groups.get(GLTF_GROUP)
    if group is not None and group.get(EXPORT_KEY) and group.users == 0:
        bpy.data.node_groups.remove(group)
    return touched
