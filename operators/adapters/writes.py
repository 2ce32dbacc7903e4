"""Writing into Blender data so that a failed or cancelled bake changes nothing.

:class:`Transaction` makes each write with the action that undoes it;
:class:`MaterialSnapshot` is enough of a material to put it back exactly;
:func:`store_float_image` is the one writer of the bake's float images, :func:`store_png_image` of the
exported PNG images;
:func:`save_image_file` writes the AO next to the .blend.
"""

import os

import bpy
import numpy as np

from ...core.arrays.graph import put_pairs
from ...core.export.png import encode_png
from ...core.keys import (AO_LAYERS, GROUP_VERSION, HELPER_KEY, IMAGE_KEY, MATERIAL_KEY, OURS_KEY, SAVE_COPY,
                          STACK_MODIFIER, VERSION_KEY)
from ...shaders import material as material_nodes
from ...shaders.node_group import find_node_group, node_group as build_node_group
from ...shaders.stack_nodes import stack_group
from . import stack
from .mesh_data import read_uv, write_uv


def corner_uv(corner_count, loops, axis_uv):
    """(3 layers, corner_count, 2) float32: the triangles' UVs ``axis_uv`` (three (t, 3, 2)) on the mesh's
    corners, ``loops`` (t, 3) saying which corner each triangle corner is."""
    per_corner = np.empty((3, corner_count, 2), dtype=np.float32)
    for axis, uv in enumerate(layers_on_corners(corner_count, loops, axis_uv)):
        per_corner[axis] = uv
    return per_corner


def layers_on_corners(corner_count, loops, layer_uvs):
    """Each layer's triangle UVs of ``layer_uvs`` (each (t, 3, 2)) on the mesh's corners, (corner_count, 2)
    float32, one layer at a time; ``loops`` (t, 3) says which corner each triangle corner is.  An all-triangle
    mesh's triangles are its corners in order (mesh_data.triangle_loops): its UVs are each layer as it is, with
    no scatter (tested once for all the layers)."""
    loops = np.asarray(loops)
    in_order = loops.size == corner_count and bool((loops.ravel() == np.arange(corner_count)).all())
    for triangle_uv in layer_uvs:
        if in_order:
            yield np.asarray(triangle_uv, dtype=np.float32).reshape(-1, 2)
        else:
            uv = np.zeros((corner_count, 2), dtype=np.float32)
            put_pairs(uv, loops, triangle_uv)
            yield uv


class Transaction:
    """Writes into Blender data, each with the action that undoes it."""

    def __init__(self):
        self.undo = []
        self.undo_first = []            # undone before the rest: the node group, before its users
        self.on_commit = []

    def roll_back(self):
        for action in self.undo_first + self.undo[::-1]:
            action()
        self.undo.clear()
        self.undo_first.clear()
        self.on_commit.clear()

    def commit(self):
        """Everything was written: drop what was kept only for a roll-back."""
        for action in self.on_commit:
            action()
        self.on_commit.clear()
        self.undo.clear()
        self.undo_first.clear()

    def node_group(self):
        """The current ``Seamless AO`` group.  An older one is rebuilt in place; until the bake is
        committed a copy of the old one is kept, so a roll-back puts it back for every material."""
        group = find_node_group()
        if group is None:
            self.undo.append(_remove_node_group_if_unused)
        elif group.get(VERSION_KEY) != GROUP_VERSION:
            backup = group.copy()
            del backup[VERSION_KEY]                   # not found as ours meanwhile

            def restore(group=group, backup=backup, name=group.name, version=group[VERSION_KEY]):
                group.user_remap(backup)
                bpy.data.node_groups.remove(group)
                backup.name = name
                backup[VERSION_KEY] = version
            # first: the materials, restored afterwards, relink to the old group's sockets; their
            # snapshots are taken now, since rebuilding the group drops their links to it
            self.undo_first.append(restore)
            for material in bpy.data.materials:
                if material.node_tree is not None and any(
                        n.bl_idname == "ShaderNodeGroup" and n.node_tree == group for n in material.node_tree.nodes):
                    self.undo.append(MaterialSnapshot(material).restore)
            self.on_commit.append(lambda backup=backup: bpy.data.node_groups.remove(backup))
        return build_node_group()

    def file(self, path, write):
        """``write(path)``, undone by putting back the file that was there (or removing the new one)."""
        old = None
        if os.path.exists(path):
            with open(path, "rb") as handle:
                old = handle.read()

        def restore(path=path, old=old):
            if old is None:
                if os.path.exists(path):
                    os.remove(path)
            else:
                with open(path, "wb") as handle:
                    handle.write(old)
        self.undo.append(restore)
        write(path)

    def set_property(self, owner, key, value):
        """``owner[key] = value``, undone by restoring (or deleting) the old value."""
        old = owner.get(key)

        def restore(owner=owner, key=key, old=old):
            if old is None:
                owner.pop(key, None)
            else:
                owner[key] = old
        self.undo.append(restore)
        owner[key] = value

    def image(self, name, values):
        """The AO image, new or (if the add-on made it) overwritten in place; packed into the .blend."""
        image, undo = store_float_image(name, values)
        self.undo.append(undo)
        return image

    def uv_maps(self, mesh, loops, axis_uv):
        """Create or replace AO_X/Y/Z; the user's active and render-active UV maps stay as they were.

        Parameters
        ----------
        loops : (t, 3) int, loop of each triangle corner
        axis_uv : three (t, 3 corners, 2), the triangles' UVs in AO_X, AO_Y and AO_Z
        """
        layers = mesh.uv_layers
        active = layers.active.name if layers.active is not None else None
        render = next((uv.name for uv in layers if uv.active_render), None)
        for name, uv in zip(AO_LAYERS, layers_on_corners(len(mesh.loops), loops, axis_uv)):
            layer = layers.get(name)
            if layer is None:
                layer = layers.new(name=name, do_init=False)
                self.undo.append(lambda mesh=mesh, name=name: mesh.uv_layers.remove(mesh.uv_layers[name]))
            else:
                self.undo.append(lambda mesh=mesh, name=name, old=read_uv(mesh, name): write_uv(mesh, name, old))
            write_uv(mesh, name, uv)
        self.undo.append(lambda mesh=mesh, active=active, render=render: _restore_active(mesh, active, render))
        _restore_active(mesh, active, render)

    def stack_uv_maps(self, ob, corners, loops, axis_uv, viewport=None, viewport_uv=None):
        """UV maps AO_X/Y/Z for an object whose stack changes its topology (or whose mesh is shared): a
        helper holding the baked corners and the maps, one for the viewport's surface where its levels
        differ, and the ``Seamless AO`` modifier, last in the stack, that stores them onto the evaluated mesh
        (:mod:`.stack`).  Helpers from an earlier bake are kept until the commit, so a roll-back puts
        everything back.

        Parameters
        ----------
        corners : mesh_data.EvaluatedCorners, the evaluated corners the bake saw
        loops : (t, 3) int, the corner of each triangle corner
        axis_uv : three (t, 3 corners, 2), the triangles' UVs in AO_X, AO_Y and AO_Z
        viewport : mesh_data.EvaluatedCorners of the surface the viewport shows, where it is not ``corners``; or None
        viewport_uv : (3 layers, its corners, 2), its UVs (:func:`...core.atlas.viewport_uv.surface_uv`)
        """
        per_corner = corner_uv(len(corners.corner_vert), loops, axis_uv)
        helpers = [self._helper(stack.helper_name(ob), corners, per_corner), None]
        if viewport is not None and viewport_uv is not None:
            helpers[1] = self._helper(stack.helper_name(ob, viewport=True), viewport, viewport_uv)
        for old in stack.helpers_of(ob):
            if old is not None and old not in helpers:
                self.on_commit.append(lambda old=old: stack.remove_helper(old))
        modifier = stack.stack_modifier(ob)
        if modifier is None:
            modifier = ob.modifiers.new(STACK_MODIFIER, "NODES")
            modifier.node_group = stack_group()
            modifier.use_pin_to_last = True                   # stays last when the artist adds modifiers
            self.undo.append(lambda ob=ob, name=modifier.name: ob.modifiers.remove(ob.modifiers[name]))
        else:
            stack_group()                               # rebuilt if a bake of an older version made it
            self.undo.append(lambda modifier=modifier, old=stack.helper_inputs(modifier):
                             stack.set_helper_inputs(modifier, *old))
            position = list(ob.modifiers).index(modifier)
            if position != len(ob.modifiers) - 1:             # the user added modifiers after it: it goes last
                ob.modifiers.move(position, len(ob.modifiers) - 1)
                self.undo.append(lambda ob=ob, name=modifier.name, position=position: ob.modifiers.move(
                    len(ob.modifiers) - 1, position))
        stack.set_helper_inputs(modifier, *helpers)
        modifier.show_viewport = modifier.show_render = True
        self.set_property(ob, HELPER_KEY, helpers[0].name)
        ob.update_tag()

    def _helper(self, name, corners, layer_uv_per_corner):
        """A new helper object (in no scene) holding ``corners``'s corners and UV maps; undone by removing it."""
        helper = bpy.data.objects.new(name, stack.helper_mesh(name, corners, layer_uv_per_corner))
        self.undo.append(lambda helper=helper: stack.remove_helper(helper))
        return helper

    def drop_stack(self, ob):
        """Take an earlier bake's modifier and helpers off ``ob`` (its stack no longer needs them: the UV maps
        go on its mesh), undone by putting them back."""
        modifier, helpers = stack.stack_modifier(ob), stack.helpers_of(ob)
        if modifier is not None:
            position = list(ob.modifiers).index(modifier)
            group, inputs, pinned = modifier.node_group, stack.helper_inputs(modifier), modifier.use_pin_to_last

            def restore(ob=ob, group=group, inputs=inputs, position=position, pinned=pinned):
                again = ob.modifiers.new(STACK_MODIFIER, "NODES")
                again.node_group = group
                stack.set_helper_inputs(again, *inputs)
                ob.modifiers.move(len(ob.modifiers) - 1, position)
                again.use_pin_to_last = pinned
            ob.modifiers.remove(modifier)
            self.undo.append(restore)
        for helper in helpers:
            if helper is not None:
                self.on_commit.append(lambda helper=helper: stack.remove_helper(helper))
        if ob.get(HELPER_KEY) is not None:
            old = ob[HELPER_KEY]
            del ob[HELPER_KEY]
            self.undo.append(lambda ob=ob, old=old: ob.__setitem__(HELPER_KEY, old))

    def materials(self, ob, image, multiply, baked_objects):
        """Hook every material of ``ob`` (giving it one if it has none)."""
        warnings = []
        if not any(slot.material for slot in ob.material_slots):
            material = material_nodes.new_material(ob.name + "_SeamlessAO")
            if ob.material_slots:
                old = ob.material_slots[0].material
                ob.material_slots[0].material = material
                self.undo.append(lambda ob=ob, old=old: setattr(ob.material_slots[0], "material", old))
            else:
                ob.data.materials.append(material)
                self.undo.append(lambda mesh=ob.data: mesh.materials.pop())
            self.undo.append(lambda material=material: bpy.data.materials.remove(material))
            self.set_property(ob, MATERIAL_KEY, material.name)
        baked_meshes = {o.data for o in baked_objects}
        for material in {slot.material for slot in ob.material_slots if slot.material is not None}:
            if material.library is not None:
                warnings.append("material '{}' is linked from a library and was left alone".format(material.name))
                continue
            snapshot = MaterialSnapshot(material)
            material_nodes.hook_material(material, image, multiply)
            self.undo.append(snapshot.restore)
            sharers = [o.name for o in bpy.data.objects if o.type == "MESH" and o.data not in baked_meshes
                       and any(s.material == material for s in o.material_slots) and o.get(IMAGE_KEY)]
            if sharers:
                warnings.append("material '{}' is also used by {}, baked separately: it now shows this bake's "
                                "image; bake them together to share one".format(material.name, ", ".join(sharers)))
        return warnings


def store_float_image(name, values, marks=(OURS_KEY,), keep_undo=True):
    """The image ``name`` holding ``values`` (height, width) as grey: float, Non-Color, packed into the .blend.

    Made new (with the custom properties ``marks`` set), or, if Seamless AO
    made it, overwritten in place.  Returns ``(image, undo)``; ``undo()`` puts
    back what was there before (``None`` with ``keep_undo`` off: the old
    pixels are then not even read).
    """
    height, width = values.shape
    image = bpy.data.images.get(name)
    if image is not None and image.get(OURS_KEY):
        undo = _pixels_undo(image) if keep_undo else None
        _regenerate(image, width, height)
    else:
        image = bpy.data.images.new(name, width, height, alpha=False, float_buffer=True)
        for key in marks:
            image[key] = True

        def undo(image=image):
            bpy.data.images.remove(image)
    if image.colorspace_settings.name != "Non-Color":
        image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(grey_pixels(values))
    image.pack()
    return image, undo


def store_png_image(name, data, marks=(OURS_KEY,)):
    """The image ``name`` holding the PNG file ``data`` (bytes), packed into the .blend, Non-Color.

    Made new with the custom properties ``marks`` set; an image of that name Seamless AO made is replaced
    (its users, such as the material nodes that read it, then read the new one); a user's image of that name
    is left alone and the new one takes the next free name.
    """
    image = bpy.data.images.new(name, 8, 8, alpha=True)
    image.pack(data=data, data_len=len(data))
    image.source = "FILE"
    image.filepath_raw = "//{}.png".format(bpy.path.clean_name(name))
    image.colorspace_settings.name = "Non-Color"
    image.alpha_mode = "CHANNEL_PACKED"                  # A, where there is one, is a value of its own
    for key in marks:
        image[key] = True
    old = bpy.data.images.get(name)
    if old is not None and old != image and old.get(OURS_KEY):
        old.user_remap(image)
        bpy.data.images.remove(old)
        image.name = name
    return image


def _pixels_undo(image):
    """A function that puts ``image``'s current size and pixels back."""
    size = tuple(image.size)
    pixels = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)

    def undo():
        _regenerate(image, *size)
        image.pixels.foreach_set(pixels)
        image.pack()
    return undo


def grey_pixels(values):
    """Flat RGBA float32 pixels of ``values`` (height, width): grey, opaque."""
    pixels = np.repeat(np.asarray(values, dtype=np.float32).reshape(-1, 1), 4, axis=1)
    pixels[:, 3] = 1.0
    return pixels.ravel()


def _regenerate(image, width, height):
    """Turn a (packed) image back into a generated float buffer of the given size, keeping the datablock."""
    image.source = "GENERATED"
    image.generated_width, image.generated_height = width, height
    image.use_generated_float = True


def _remove_node_group_if_unused():
    group = find_node_group()
    if group is not None and group.users == 0:
        bpy.data.node_groups.remove(group)


def _restore_active(mesh, active, render):
    layers = mesh.uv_layers
    if active is not None and active in layers:
        layers.active = layers[active]
    if render is not None and render in layers:
        layers[render].active_render = True


class MaterialSnapshot:
    """Enough of a material's node tree to put it back exactly: the nodes we add and the links we change."""

    def __init__(self, material):
        self.material = material
        self.had_nodes = material_nodes.uses_nodes(material)
        self.keys = {k: material[k] for k in material.keys()}
        tree = material.node_tree
        self.ours = set()
        self.links = []
        self.values = {}
        self.images = {}
        if tree is not None:
            self.ours = {n.name for n in tree.nodes if material_nodes.is_ours(n)}
            self.images = {n.name: n.image for n in tree.nodes
                           if material_nodes.is_ours(n) and n.bl_idname == "ShaderNodeTexImage"}
            self.links = [(l.from_node.name, l.from_socket.identifier, l.to_node.name, l.to_socket.identifier)
                          for l in tree.links]
            for node in tree.nodes:
                if node.bl_idname == "ShaderNodeBsdfPrincipled":
                    self.values[node.name] = tuple(node.inputs["Base Color"].default_value)

    def restore(self):
        material = self.material
        tree = material.node_tree
        if tree is not None:
            for node in [n for n in tree.nodes if material_nodes.is_ours(n) and n.name not in self.ours]:
                tree.nodes.remove(node)
            for link in list(tree.links):
                tree.links.remove(link)
            for from_node, from_socket, to_node, to_socket in self.links:
                source, target = tree.nodes.get(from_node), tree.nodes.get(to_node)
                if source is not None and target is not None:
                    tree.links.new(material_nodes.socket_named(source.outputs, from_socket),
                                   material_nodes.socket_named(target.inputs, to_socket))
            for name, value in self.values.items():
                tree.nodes[name].inputs["Base Color"].default_value = value
            for name, image in self.images.items():
                if tree.nodes.get(name) is not None:
                    tree.nodes[name].image = image
        for key in [k for k in material.keys() if k not in self.keys]:
            del material[key]
        if material_nodes.uses_nodes(material) != self.had_nodes:
            material.use_nodes = self.had_nodes


def image_file_path(image, kind):
    """Where ``save_image`` writes: next to the .blend, named after the image."""
    folder = os.path.dirname(bpy.path.abspath(bpy.data.filepath))
    return os.path.join(folder, image.name + (".png" if kind == "PNG" else ".exr"))


def save_image_file(path, image, values, kind):
    """Write the AO to ``path``: 16-bit greyscale PNG or 32-bit float OpenEXR."""
    if kind == "PNG":
        with open(path, "wb") as handle:
            handle.write(encode_png(values[::-1], 16))
        return
    copy = bpy.data.images.new(SAVE_COPY, image.size[0], image.size[1], alpha=False, float_buffer=True)
    try:
        copy.colorspace_settings.name = "Non-Color"
        copy.pixels.foreach_set(grey_pixels(values))
        copy.filepath_raw = path
        copy.file_format = "OPEN_EXR"
        copy.save()
    finally:
        bpy.data.images.remove(copy)
