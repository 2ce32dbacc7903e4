"""The Cycles ray caster: the Geometry Nodes caster, plus Cycles' AO bake for the bulk of each texel's rays.

Blender's Raycast node finds the nearest hit of every ray; AO only asks
whether a ray meets anything, which Cycles (Embree) answers faster, most of
all in closed rooms.  Cycles casts no given rays, but it bakes AO into an
image: :meth:`CyclesAmbientOcclusion.ambient_occlusion` makes a mesh of one tiny
triangle per texel (at the texel's ray origin, facing its shading normal,
so that Cycles' normal there is the texel's with no custom normals to set;
a UV triangle around a pixel of its own), invisible to every ray, and bakes
Cycles' AO of it into a float image in the caster's temporary scene, where
the occluder is the same mesh the Raycast node sees.  Each texel's pixel is
its open fraction.

:class:`...core.rays.job.AOJob` still casts each texel's first few rays with the
Raycast node (they say which texels are buried inside another piece, which
Cycles' AO cannot say), and the rays that find the crease points; it hands
the remaining rays, and the AO at the crease points, to Cycles.  The
settings Cycles' AO cannot follow (falloff, cone, ground plane, back faces)
are refused by :class:`...core.settings.BakeSettings`.
Everything is made in the temporary scene and removed with the caster; the
user's scenes and render settings are not touched.
"""

import bpy
import numpy as np

from ...core.errors import SeamlessAOError
from ...core.freed_memory import give_back_freed_memory
from ...core.keys import TEMP_PREFIX
from ...core.rays.ao import ray_origins
from .cycles_device import cycles_device
from .mesh_data import mesh_from_triangles

#: Half-size of each texel's triangle, relative to the ray origin offset (far below a texel, and the
#: triangle is invisible to rays anyway).
TRIANGLE_SIZE = 0.5
#: Width of the image the texels are baked into (one pixel per texel, row by row).
IMAGE_WIDTH = 2048
#: Ray kinds the texel mesh is hidden from: it must never occlude.
HIDDEN_FROM = ("visible_diffuse", "visible_glossy", "visible_transmission",
               "visible_volume_scatter", "visible_shadow")


def cycles_enabled():
    """Whether the Cycles render engine is enabled in this Blender (its add-on registered; a user may turn it
    off in the Preferences)."""
    return hasattr(bpy.types.Scene, "cycles")


def texel_triangles(origins, normals, geometric, size):
    """One small triangle per texel, in the plane of its shading normal, wound to face it: a flat
    triangle's normal is the one Cycles shades with, so the texel's hemisphere needs no custom normals
    (setting them took about half of the call's time outside the bake).

    Parameters
    ----------
    origins, normals, geometric : (k, 3) float64, ray space; ``geometric`` unit length (the facing where a
        shading normal is not a direction)
    size : float, the triangles' half-size (ray space units)

    Returns
    -------
    corners : (k, 3, 3) float64
    """
    length = np.sqrt((normals * normals).sum(axis=1))[:, None]
    facing = np.where(length > 0.5, normals / np.maximum(length, 1e-300), geometric)
    helper = np.where(np.abs(facing[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    first = np.cross(facing, helper)
    first /= np.maximum(np.sqrt((first * first).sum(axis=1)), 1e-300)[:, None]
    second = np.cross(facing, first)                     # first, second, facing: right-handed
    return np.stack([origins - size * (first + 0.5 * second), origins + size * (first - 0.5 * second),
                     origins + size * second], axis=1)


def pixel_uv(count, width):
    """UV triangles (k, 3, 2) around the centres of pixels 0..count-1 of a ``width``-wide image, row by row,
    and the image's height."""
    height = max(1, -(-count // width))
    index = np.arange(count)
    centre = np.stack([index % width, index // width], axis=1) + 0.5
    uv = centre[:, None, :] + np.array([[-0.45, -0.3], [0.45, -0.3], [0.0, 0.45]])
    return uv / np.array([width, height], dtype=np.float64), height


class CyclesAmbientOcclusion:
    """``ambient_occlusion``, Cycles' AO baked at given texels, for a caster with a temporary ``scene``, its
    ``occluder`` object, ``_temporary`` (datablocks removed with the caster), ``device`` (None until the first
    bake chooses it) and ``warnings``: :class:`.casters.CyclesCaster` is :class:`.casters.NodesCaster` with
    it."""

    def ambient_occlusion(self, points, normals, geometric, samples, params):
        """Cycles' AO of ``samples`` rays at each point (k, 3), ray space: the open fraction (k,) in [0, 1].

        The ray origin is the one :func:`...core.rays.ao.occlusion_sums` casts from
        (:func:`...core.rays.ao.ray_origins`).  The maximum distance is ``params.max_distance``.
        """
        count = len(points)
        if not count:
            return np.zeros(0)
        if not cycles_enabled():
            raise SeamlessAOError("The Cycles ray caster needs the Cycles render engine, which is not enabled "
                                  "in this Blender; enable it, or choose the Geometry Nodes caster.")
        made = []
        try:
            # the texel mesh's float64 sources (about 200 bytes a texel) are let go before Cycles runs
            mesh, height = _texel_mesh(*ray_origins(points, normals, geometric, params.offset), normals,
                                       TRIANGLE_SIZE * params.offset)
            made.append(mesh)
            if self.device is None:
                self.device, warning = cycles_device()
                self.warnings += [warning] if warning else []
            try:
                return self._bake(mesh, height, count, samples, params)
            except SeamlessAOError as error:
                if self.device != "GPU":
                    raise
                # out of GPU memory, a driver fault: the CPU bakes it, and the report says so
                self.device = "CPU"
                self.warnings.append("Cycles could not bake on the GPU ({}): it baked on the CPU".format(error))
                return self._bake(mesh, height, count, samples, params)
        finally:
            if made:
                bpy.data.batch_remove(made)

    def _bake(self, mesh, height, count, samples, params):
        """Cycles' AO bake of the texel mesh ``mesh`` (:func:`_texel_mesh`) into one image row by row."""
        # Cycles takes its memory afresh: what the rays before it freed goes back first (core/freed_memory.py)
        give_back_freed_memory(len(self.occluder.data.polygons))
        made = []
        try:
            image = _made(made, bpy.data.images.new(TEMP_PREFIX + "texels", IMAGE_WIDTH, height, alpha=False,
                                                     float_buffer=True))
            image.colorspace_settings.name = "Non-Color"
            material = _made(made, bpy.data.materials.new(TEMP_PREFIX + "texels"))
            if material.node_tree is None:
                material.use_nodes = True
            # No surface shader at all: Cycles would evaluate a Principled BSDF at every sample (it took
            # 2-3x as long per sample with one); the AO needs only the mesh's normal.
            material.node_tree.nodes.clear()
            node = material.node_tree.nodes.new("ShaderNodeTexImage")
            node.image = image
            material.node_tree.nodes.active = node
            mesh.materials.clear()                     # a failed GPU bake left an empty slot
            mesh.materials.append(material)
            texels = _made(made, bpy.data.objects.new(TEMP_PREFIX + "texels", mesh))
            for name in HIDDEN_FROM:
                setattr(texels, name, False)
            self.scene.collection.objects.link(texels)
            self._set_up_cycles(samples, params)
            view_layer = self.scene.view_layers[0]
            with bpy.context.temp_override(scene=self.scene, view_layer=view_layer, active_object=texels,
                                           object=texels, selected_objects=[texels],
                                           selected_editable_objects=[texels]):
                result = bpy.ops.object.bake(type="AO", margin=0, use_clear=True, target="IMAGE_TEXTURES")
            if "FINISHED" not in result:
                raise SeamlessAOError("Cycles did not bake the AO ({}); choose the Geometry Nodes caster."
                                      .format(", ".join(sorted(result))))
            pixels = np.empty(IMAGE_WIDTH * height * 4, dtype=np.float32)
            image.pixels.foreach_get(pixels)
            return pixels.reshape(-1, 4)[:count, 0].astype(np.float64)
        except RuntimeError as error:                  # what bpy.ops raises with Cycles' own message
            raise SeamlessAOError("Cycles could not bake the AO: {}".format(str(error).strip())) from error
        finally:
            if made:
                bpy.data.batch_remove(made)

    def _set_up_cycles(self, samples, params):
        """The temporary scene's render settings for a plain AO bake (only this scene is changed)."""
        scene = self.scene
        self.occluder.hide_render = False              # Cycles must see it (the Raycast node reads it either way)
        scene.render.engine = "CYCLES"
        if scene.world is None:
            scene.world = self._temporary(bpy.data.worlds.new(TEMP_PREFIX + "world"))
        scene.world.light_settings.distance = float(params.max_distance)
        cycles = scene.cycles
        cycles.device = self.device                     # the user's, from Cycles' preferences (.cycles_device)
        cycles.samples = int(samples)
        cycles.seed = int(params.seed) & 0x7FFFFFFF
        cycles.use_animated_seed = False
        cycles.use_denoising = False
        cycles.use_adaptive_sampling = False
        cycles.max_bounces = 0
        cycles.diffuse_bounces = 0


def _texel_mesh(origins, geometric, normals, size):
    """A new mesh of one tiny triangle per texel (:func:`texel_triangles`), each with a UV triangle around
    a pixel of its own (:func:`pixel_uv`), and the height of the image those pixels fill."""
    count = len(origins)
    mesh = mesh_from_triangles(TEMP_PREFIX + "texels", texel_triangles(origins, normals, geometric, size)
                               .reshape(-1, 3), np.arange(3 * count, dtype=np.int32).reshape(-1, 3))
    uv, height = pixel_uv(count, IMAGE_WIDTH)
    mesh.uv_layers.new(name="texels").data.foreach_set("uv", uv.astype(np.float32).ravel())
    return mesh, height


def _made(made, datablock):
    made.append(datablock)
    return datablock
