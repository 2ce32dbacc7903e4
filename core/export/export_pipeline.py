"""The export on arrays, the twin of :mod:`..pipeline`: a bake read as it renders in, PNG bytes or colours out.

The Blender side reads an object into a :class:`BakedSurface` (and, for a
packing that carries the material, its slots into :class:`SlotMaterials`),
calls :func:`resampled_image` or :func:`color_values`, and writes what comes
back; every decision (which settings refuse, whether the UV map can hold the
AO, what each triangle's material says, how the channels are packed) is made
here::

    surface = BakedSurface(ao_image, layer_uv, corner_normals, triangle_area, degenerate, triangle_slot)
    png = resampled_image(surface, target_uv, settings, "Suzanne", "UVMap", slot_materials)   # bytes
"""

from dataclasses import dataclass, field

import numpy as np

from ..errors import SeamlessAOError
from .packings import BY_ID
from .transfer import corner_values, resample_to_uv, resampled_png, vertex_average
from .uv_fitness import uv_fitness


@dataclass
class BakedSurface:
    """One baked object as it renders, and its material slots' ``Seamless AO`` node inputs.

    Attributes
    ----------
    ao_image : (h, w) float64, the baked atlas
    layer_uv : (t, 3 layers, 3 corners, 2) float64, each triangle's AO_X/Y/Z UVs
    corner_normals : (t, 3, 3) float64, object-space shading normals at the corners
    triangle_area : (t,) float64, each triangle's area (scene units²)
    degenerate : (t,) bool, triangles with no area to lay out
    triangle_slot : (t,) int, each triangle's material slot (already clipped to the slots there are)
    slot_blend : (s, 2) float64, each slot's node inputs (strength, interreflection); (1, 0) where a slot's
        material has no node
    """

    ao_image: np.ndarray
    layer_uv: np.ndarray
    corner_normals: np.ndarray
    triangle_area: np.ndarray
    degenerate: np.ndarray
    triangle_slot: np.ndarray
    slot_blend: np.ndarray = field(default_factory=lambda: np.array([[1.0, 0.0]]))

    def node_inputs(self, use):
        """(strength, interreflection): (t,) each, the node inputs of every triangle's slot, or (1, 0) when
        ``use`` (the Material Strength setting) is off."""
        if not use:
            return 1.0, 0.0
        per_triangle = np.asarray(self.slot_blend, dtype=np.float64)[self.triangle_slot]
        return per_triangle[:, 0], per_triangle[:, 1]


@dataclass
class SlotMaterials:
    """What each material slot says of roughness and metallic, for a packing that carries them.

    Attributes
    ----------
    values : (s, 2) float64, each slot's roughness and metallic (a Principled BSDF's own inputs; 0.5 and 0
        without one)
    texture_use : (s, k) bool, where slot ``s`` reads its value from texture ``k`` instead
    textures : list of k ``(value, texels)``: ``value`` 0 roughness or 1 metallic, ``texels`` (h', w') float64,
        a texture channel read through the UV map the export lays the AO on
    """

    values: np.ndarray
    texture_use: np.ndarray
    textures: list

    def per_triangle(self, triangle_slot):
        """(t, 2 + k) float64: each triangle's roughness and metallic, then 1 per texture it reads (the columns
        :func:`..export.transfer.packed_values` replaces by the texture's own texels)."""
        table = np.concatenate([np.asarray(self.values, dtype=np.float64).reshape(-1, 2),
                                np.asarray(self.texture_use, dtype=np.float64).reshape(len(self.values), -1)], axis=1)
        return table[triangle_slot]


def export_packing(settings):
    """The :class:`~.packings.Packing` an export writes, refused with a sentence where the glTF occlusion
    cannot read it."""
    packing = BY_ID[settings.packing]
    if settings.gltf_occlusion and not packing.gltf_readable:
        raise SeamlessAOError(packing.not_gltf() + ": turn glTF occlusion off to write one")
    return packing


def resampled_image(surface, target_uv, settings, object_name, uv_map, materials=None):
    """The PNG bytes of ``surface``'s AO laid on its UV map ``uv_map``, as the ``Seamless AO`` node shows it.

    Parameters
    ----------
    surface : :class:`BakedSurface`
    target_uv : (t, 3, 2) float64, the UV map at each triangle corner
    settings : :class:`~..settings.ExportSettings` (size, padding, packing, bit depth, material strength,
        whether an unfit UV map is refused)
    object_name, uv_map : str, for the sentence that refuses a UV map that cannot hold the AO
    materials : :class:`SlotMaterials`, needed where the packing carries the material

    Returns
    -------
    bytes, an RGB(A) or grey PNG, ``settings.size`` texels square
    """
    packing = export_packing(settings)
    if not settings.unfit_uv_map:
        fitness = uv_fitness(target_uv, surface.triangle_area)
        if not fitness.can_hold_ao:
            raise SeamlessAOError("'{}': its UV map '{}' cannot hold the AO: {}; pick another UV map, or resample "
                                  "anyway (Even If Unfit)".format(object_name, uv_map, "; ".join(fitness.problems())))
    carried, textures = None, []
    if packing.carries_material:
        if materials is None:
            raise ValueError("the {} packing carries the material: give its SlotMaterials".format(packing.id))
        carried, textures = materials.per_triangle(surface.triangle_slot), materials.textures
    laid = resample_to_uv(surface.ao_image, surface.layer_uv, surface.corner_normals, target_uv,
                          settings.size, settings.padding, surface.degenerate,
                          *surface.node_inputs(settings.material_strength), per_triangle=carried)
    return resampled_png(laid, settings.packing, settings.bit_depth, textures)


def color_values(surface, settings, triangle_loops, loop_count, loop_vertex=None, vertex_count=0):
    """The AO the ``Seamless AO`` node shows, per face corner or per vertex, for a colour attribute.

    Parameters
    ----------
    surface : :class:`BakedSurface`
    settings : :class:`~..settings.ExportSettings` (domain, material strength)
    triangle_loops : (t, 3) int, the mesh's face corner (loop) of each triangle corner
    loop_count : int, the mesh's face corners
    loop_vertex : (loop_count,) int, each corner's vertex (for the POINT domain)
    vertex_count : int

    Returns
    -------
    (loop_count,) float64 for the CORNER domain, (vertex_count,) float64 for POINT (the mean of its corners);
    1 (open) where no triangle reaches
    """
    values = corner_values(surface.ao_image, surface.layer_uv, surface.corner_normals,
                           *surface.node_inputs(settings.material_strength))            # (t, 3)
    per_loop = np.ones(loop_count)
    per_loop[np.asarray(triangle_loops).ravel()] = values.ravel()
    if settings.domain == "POINT":
        return vertex_average(per_loop, loop_vertex, vertex_count)
    return per_loop
