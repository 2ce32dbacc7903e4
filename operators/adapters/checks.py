"""Input a bake refuses, each with one sentence, and the fingerprint that notices edits during a bake."""

import zlib

import bpy
import numpy as np

from ...core.errors import SeamlessAOError
from ...core.keys import AO_LAYERS, MAX_UV_MAPS
from ...core.mesh.triangle_mesh import flattened
from .mesh_data import loop_vertices, vertex_positions


def check_objects(objects, settings):
    """Raise :class:`SeamlessAOError` with one clear sentence for input that cannot be baked."""
    if not objects:
        raise SeamlessAOError("Select a mesh object to bake")
    for ob in objects:
        if ob is not None and ob.type == "EMPTY" and ob.instance_type == "COLLECTION" and ob.instance_collection:
            raise SeamlessAOError(
                "'{}' instances the collection '{}', whose objects are shared with every other instance; bake "
                "the objects inside it, or make this instance real first (Object > Apply > Make Instances "
                "Real)".format(ob.name, ob.instance_collection.name))
        if ob is None or ob.type != "MESH":
            raise SeamlessAOError("'{}' is not a mesh; Seamless AO bakes mesh objects only".format(
                getattr(ob, "name", ob)))
        if ob.library is not None or ob.data.library is not None:
            raise SeamlessAOError("'{}' is linked from a library and cannot be changed; make it local first".format(
                ob.name))
        if ob.mode == "EDIT":
            raise SeamlessAOError("'{}' is in Edit Mode; press Tab to leave it before baking".format(ob.name))
        if not len(ob.data.polygons) and not any(m.show_render for m in ob.modifiers):
            raise SeamlessAOError("'{}' has no faces to bake (only vertices or loose edges)".format(ob.name))
        if flattened(np.array(ob.matrix_world, dtype=np.float64)[:3, :3]):
            raise SeamlessAOError(
                "'{}' is scaled to zero along an axis (its own or a parent's scale), so it has no surface to "
                "bake; give it a non-zero scale".format(ob.name))
        others = [uv.name for uv in ob.data.uv_layers if uv.name not in AO_LAYERS]
        if len(others) + len(AO_LAYERS) > MAX_UV_MAPS:
            raise SeamlessAOError(
                "'{}' already has {} UV maps; Blender allows {} and Seamless AO needs 3 more (AO_X, AO_Y, AO_Z): "
                "remove {} to bake".format(ob.name, len(others), MAX_UV_MAPS,
                                           len(others) + len(AO_LAYERS) - MAX_UV_MAPS))
    if settings.save_image != "NONE" and not bpy.data.filepath:
        raise SeamlessAOError("Save the .blend file first: the AO image is written next to it")


def mesh_fingerprint(ob):
    """What a bake's writes rely on, cheaply: the object's mesh, its counts, a checksum of its vertex
    positions and of its loops' vertices (a few ms for a million vertices)."""
    mesh = ob.data
    return (mesh.as_pointer(), len(mesh.vertices), len(mesh.loops), len(mesh.polygons),
            zlib.crc32(vertex_positions(mesh).tobytes()), zlib.crc32(loop_vertices(mesh).tobytes()))


def check_unchanged(objects, fingerprints):
    """Refuse to write if a baked object was deleted, edited or put in Edit Mode since it was read
    (the interactive bake lets the user work meanwhile; undo also replaces objects)."""
    for ob, fingerprint in zip(objects, fingerprints):
        try:
            name = ob.name
            changed = ob.mode == "EDIT" or mesh_fingerprint(ob) != fingerprint
        except ReferenceError:
            raise SeamlessAOError(
                "An object being baked was deleted or undone during the bake; nothing was written") from None
        if changed:
            raise SeamlessAOError(
                "'{}' was edited during the bake, so the AO no longer fits its mesh; nothing was written: "
                "bake again".format(name))
