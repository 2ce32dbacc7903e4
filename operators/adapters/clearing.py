"""``clear(objects)``: remove exactly what bakes and exports added, nothing the user made."""

import bpy

from ...core.keys import AO_LAYERS, CREATED_KEY, HELPER_KEY, IMAGE_KEY, MATERIAL_KEY, OURS_KEY
from ...shaders import material as material_nodes
from ...shaders.node_group import find_node_group
from ...shaders.stack_nodes import find_stack_group
from . import stack
from .exports import clear_exports


def clear(objects):
    """Remove exactly what bakes added to ``objects``: UV maps, nodes, created materials, unused images.

    Returns the number of objects that had anything to remove.
    """
    cleared = 0
    for ob in objects:
        if ob is None or ob.type != "MESH":
            continue
        touched = False
        mesh = ob.data
        modifier, helpers = stack.stack_modifier(ob), stack.helpers_of(ob)
        if modifier is not None:
            ob.modifiers.remove(modifier)
            touched = True
        for helper in helpers:
            if helper is not None:
                stack.remove_helper(helper)
                touched = True
        if ob.get(HELPER_KEY) is not None:
            del ob[HELPER_KEY]
        for name in AO_LAYERS:
            layer = mesh.uv_layers.get(name)
            if layer is not None:
                mesh.uv_layers.remove(layer)
                touched = True
        for material in {slot.material for slot in ob.material_slots if slot.material is not None}:
            if material.node_tree is not None and any(material_nodes.is_ours(n) for n in material.node_tree.nodes):
                material_nodes.unhook_material(material)
                touched = True
        created = ob.get(MATERIAL_KEY)
        if created:
            material = bpy.data.materials.get(created)
            if material is not None and material.get(CREATED_KEY):
                index = mesh.materials.find(material.name)
                if index >= 0:
                    mesh.materials.pop(index=index)
                if material.users == 0:
                    bpy.data.materials.remove(material)
            del ob[MATERIAL_KEY]
            touched = True
        touched |= clear_exports(ob)
        image_name = ob.get(IMAGE_KEY)
        if image_name:
            image = bpy.data.images.get(image_name)
            if image is not None and image.get(OURS_KEY) and image.users == 0:
                bpy.data.images.remove(image)
            del ob[IMAGE_KEY]
            touched = True
        cleared += touched
    for group in (find_node_group(), find_stack_group()):
        if group is not None and group.users == 0:
            bpy.data.node_groups.remove(group)
    return cleared
