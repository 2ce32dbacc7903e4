"""Hook the ``Seamless AO`` group into materials, and take it out again exactly.

Every node the add-on adds is named ``SeamlessAO ...`` and sits in one frame
labelled "Seamless AO", so a re-bake finds and updates the same nodes (never
piles up duplicates) and Clear removes exactly those.  Where the AO is
multiplied into a Principled BSDF's Base Color, the Multiply node's first
input keeps what Base Color had (its link or its value), which is what Clear
puts back.
"""

import bpy

from ..core.keys import (AO_LAYERS, AXES, BLEND, CREATED_KEY, FRAME, NODE_PREFIX, NODES_KEY, PREVIEW, STALE_ATTRIBUTE,
                         STALE_NODE, SURFACE_KEY)
from .node_group import node_group


def uses_nodes(material):
    """Whether the material renders with its node tree (``use_nodes`` is always on from Blender 5.0)."""
    if material.node_tree is None:
        return False
    return bpy.app.version >= (5, 0, 0) or material.use_nodes


def enable_nodes(material):
    """Switch the node tree on (Blender 4.x); returns True if it was off."""
    if uses_nodes(material):
        return False
    material.use_nodes = True
    return True


def image_node_name(axis):
    return NODE_PREFIX + "Image " + axis


def uv_node_name(axis):
    return NODE_PREFIX + "UV " + axis


def multiply_node_name(principled):
    return NODE_PREFIX + "Multiply " + principled.name


def is_ours(node):
    return node.name.startswith(NODE_PREFIX)


def blend_inputs(material):
    """(Strength, Interreflection) set on the material's ``Seamless AO`` node: what its output applies to
    the baked AO.  (1, 0), the AO as baked, where the material has no such node; an input driven by a
    link counts with its unlinked value."""
    node = material.node_tree.nodes.get(BLEND) if material is not None and material.node_tree else None
    if node is None or node.bl_idname != "ShaderNodeGroup":
        return 1.0, 0.0
    return float(node.inputs["Strength"].default_value), float(node.inputs["Interreflection"].default_value)


#: The outputs of a Separate Color (RGB) or Separate RGB node, by channel.
SEPARATED = {"Red": 0, "Green": 1, "Blue": 2, "R": 0, "G": 1, "B": 2}


def principled_bsdf(material):
    """The material's first Principled BSDF node, or None."""
    if material is None or material.node_tree is None:
        return None
    return next((n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"), None)


def principled_values(material, default_uv_map):
    """How the material's first Principled BSDF sets Roughness and Metallic: ``{name: (value, texture)}``, value
    the input's own value (0.5 and 0 without a Principled BSDF), texture ``(image, channel, uv_map)`` when one
    channel of an Image Texture feeds the input through a Separate Color (RGB) node, as a metallic-roughness
    texture does (channel 0..2 for R, G, B; uv_map the UV Map node's map on the texture's Vector, or
    ``default_uv_map``, the object's render-active map, where there is none), else None (any other link: the
    value counts)."""
    principled = principled_bsdf(material)
    if principled is None:
        return {"Roughness": (0.5, None), "Metallic": (0.0, None)}
    return {name: (float(principled.inputs[name].default_value),
                   _texture_channel(principled.inputs[name], default_uv_map))
            for name in ("Roughness", "Metallic")}


def _texture_channel(socket, default_uv_map):
    """``(image, channel, uv_map)`` of an input fed by Image Texture -> Separate Color (RGB), else None."""
    if not socket.is_linked:
        return None
    link = socket.links[0]
    split = link.from_node
    if split.bl_idname not in ("ShaderNodeSeparateColor", "ShaderNodeSeparateRGB") or \
            getattr(split, "mode", "RGB") != "RGB" or link.from_socket.name not in SEPARATED:
        return None
    colour = split.inputs[0]
    texture = colour.links[0].from_node if colour.is_linked else None
    if texture is None or texture.bl_idname != "ShaderNodeTexImage" or texture.image is None:
        return None
    vector = texture.inputs["Vector"]
    if not vector.is_linked:
        uv_map = default_uv_map
    elif vector.links[0].from_node.bl_idname == "ShaderNodeUVMap":
        uv_map = vector.links[0].from_node.uv_map or default_uv_map
    else:
        return None                                           # a mapping we cannot follow: the value counts
    return texture.image, SEPARATED[link.from_socket.name], uv_map


def socket_named(sockets, identifier):
    return next(s for s in sockets if s.identifier == identifier)


def hook_material(material, image, multiply=True):
    """Add (or update) the AO nodes in ``material``, reading ``image``.

    Parameters
    ----------
    material : bpy.types.Material
    image : bpy.types.Image
    multiply : bool
        Multiply the AO into the Base Color of every Principled BSDF; if False,
        only the nodes are added (and an earlier multiply is undone).
    """
    if enable_nodes(material):
        material[NODES_KEY] = True
    tree = material.node_tree
    nodes, links = tree.nodes, tree.links
    user_nodes = [n for n in nodes if not is_ours(n)]
    left = min((n.location.x for n in user_nodes), default=0.0) - 700.0
    top = max((n.location.y for n in user_nodes), default=0.0)

    frame = nodes.get(FRAME) or nodes.new("NodeFrame")
    frame.name, frame.label = FRAME, "Seamless AO"
    group_node = nodes.get(BLEND) or nodes.new("ShaderNodeGroup")
    group_node.name, group_node.label = BLEND, "Seamless AO"
    group_node.node_tree = node_group()
    group_node.parent = frame
    group_node.location = (left + 450.0, top)
    for row, (axis, layer) in enumerate(zip(AXES, AO_LAYERS)):
        uv = nodes.get(uv_node_name(axis)) or nodes.new("ShaderNodeUVMap")
        uv.name, uv.label = uv_node_name(axis), layer
        uv.uv_map = layer
        uv.parent = frame
        uv.location = (left, top - 200.0 * row)
        texture = nodes.get(image_node_name(axis)) or nodes.new("ShaderNodeTexImage")
        texture.name, texture.label = image_node_name(axis), "AO " + axis
        texture.image = image
        texture.interpolation = "Linear"
        texture.extension = "EXTEND"
        texture.parent = frame
        texture.location = (left + 180.0, top - 200.0 * row)
        links.new(uv.outputs["UV"], texture.inputs["Vector"])
        links.new(texture.outputs["Color"], group_node.inputs["AO " + axis])
    stale = nodes.get(STALE_NODE) or nodes.new("ShaderNodeAttribute")
    stale.name, stale.label = STALE_NODE, "Stale AO"
    stale.attribute_type = "GEOMETRY"
    stale.attribute_name = STALE_ATTRIBUTE
    stale.parent = frame
    stale.location = (left + 180.0, top - 600.0)
    links.new(stale.outputs["Fac"], group_node.inputs["Stale"])

    for principled in [n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"]:
        existing = nodes.get(multiply_node_name(principled))
        if multiply and existing is None:
            _insert_multiply(tree, principled, group_node)
        elif not multiply and existing is not None:
            _remove_multiply(tree, existing, principled)
    return group_node


def _insert_multiply(tree, principled, group_node):
    nodes, links = tree.nodes, tree.links
    base = principled.inputs["Base Color"]
    mix = nodes.new("ShaderNodeMix")
    mix.name, mix.label = multiply_node_name(principled), "Multiply AO"
    mix.data_type = "RGBA"
    mix.blend_type = "MULTIPLY"
    mix.location = (principled.location.x - 220.0, principled.location.y + 160.0)
    socket_named(mix.inputs, "Factor_Float").default_value = 1.0
    original = socket_named(mix.inputs, "A_Color")
    if base.is_linked:
        links.new(base.links[0].from_socket, original)
    else:
        original.default_value = tuple(base.default_value)
    links.new(group_node.outputs["AO"], socket_named(mix.inputs, "B_Color"))
    links.new(socket_named(mix.outputs, "Result_Color"), base)


def _remove_multiply(tree, mix, principled):
    """Put back what Base Color had before the multiply, then delete the node."""
    original = socket_named(mix.inputs, "A_Color")
    if principled is not None:
        base = principled.inputs["Base Color"]
        if original.is_linked:
            tree.links.new(original.links[0].from_socket, base)
        else:
            for link in list(base.links):
                tree.links.remove(link)
            base.default_value = tuple(original.default_value)
    tree.nodes.remove(mix)


def _active_output(tree):
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    return next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)


def set_material_preview(material, enabled):
    """Show only the AO (as emission) in ``material``, or put its own surface back."""
    tree = material.node_tree if uses_nodes(material) else None
    if tree is None or tree.nodes.get(BLEND) is None:
        return False
    nodes, links = tree.nodes, tree.links
    output = _active_output(tree)
    if output is None:
        return False
    surface = output.inputs["Surface"]
    preview = nodes.get(PREVIEW)
    if enabled:
        if preview is None:
            preview = nodes.new("ShaderNodeEmission")
            preview.name, preview.label = PREVIEW, "AO Preview"
            preview.parent = nodes.get(FRAME)
            blend = nodes[BLEND]
            preview.location = (blend.location.x + 220.0, blend.location.y)
            links.new(blend.outputs["AO"], preview.inputs["Color"])
        if SURFACE_KEY not in material:
            material[SURFACE_KEY] = (
                "{}|{}".format(surface.links[0].from_node.name, surface.links[0].from_socket.identifier)
                if surface.is_linked else "")
        links.new(preview.outputs["Emission"], surface)
        return True
    _restore_surface(material, tree, surface)
    if preview is not None:
        nodes.remove(preview)
    return True


def _restore_surface(material, tree, surface):
    if SURFACE_KEY not in material:
        return
    source = material[SURFACE_KEY]
    del material[SURFACE_KEY]
    for link in list(surface.links):
        tree.links.remove(link)
    if source:
        node_name, identifier = source.split("|", 1)
        node = tree.nodes.get(node_name)
        if node is not None:
            tree.links.new(socket_named(node.outputs, identifier), surface)


def unhook_material(material):
    """Remove every node the add-on added, putting Base Color and Surface back."""
    if not uses_nodes(material):
        return
    tree = material.node_tree
    set_material_preview(material, False)
    for mix in [n for n in tree.nodes if n.name.startswith(NODE_PREFIX + "Multiply ")]:
        principled = tree.nodes.get(mix.name[len(NODE_PREFIX + "Multiply "):])
        _remove_multiply(tree, mix, principled)
    for node in [n for n in tree.nodes if is_ours(n)]:
        tree.nodes.remove(node)
    if material.get(NODES_KEY):
        del material[NODES_KEY]
        material.use_nodes = False


def new_material(name):
    """A plain material for an object that had none (remembered, so Clear can remove it)."""
    material = bpy.data.materials.new(name)
    enable_nodes(material)
    material[CREATED_KEY] = True
    return material
