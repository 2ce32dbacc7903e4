"""The nodes through which Blender's glTF exporter finds a resampled AO image: UV Map -> Image Texture -> Separate
Color (R) -> the ``glTF Material Output`` group's Occlusion, in a material's Seamless AO frame."""

import bpy

from ..core.keys import BLEND, EXPORT_KEY, FRAME, GLTF_GROUP, GLTF_NODES
from . import material as material_nodes


def _gltf_group():
    group = bpy.data.node_groups.get(GLTF_GROUP)
    if group is None or group.bl_idname != "ShaderNodeTree":
        group = bpy.data.node_groups.new(GLTF_GROUP, "ShaderNodeTree")
        group.interface.new_socket("Occlusion", in_out="INPUT", socket_type="NodeSocketFloat")
        thickness = group.interface.new_socket("Thickness", in_out="INPUT", socket_type="NodeSocketFloat")
        thickness.default_value = 0.0
        group.nodes.new("NodeGroupInput")
        group.nodes.new("NodeGroupOutput")
        group[EXPORT_KEY] = True
    return group


def hook_gltf_occlusion(material, image, uv_map):
    """UV Map -> Image Texture (R) -> glTF Material Output > Occlusion, in the Seamless AO frame."""
    material_nodes.enable_nodes(material)
    tree = material.node_tree
    nodes, links = tree.nodes, tree.links
    frame = nodes.get(FRAME)
    made = []
    for name, kind in zip(GLTF_NODES, ("ShaderNodeUVMap", "ShaderNodeTexImage", "ShaderNodeSeparateColor",
                                       "ShaderNodeGroup")):
        node = nodes.get(name) or nodes.new(kind)
        node.name, node.label = name, name.replace("SeamlessAO ", "")
        node.parent = frame
        made.append(node)
    uv, texture, split, output = made
    uv.uv_map = uv_map
    texture.image = image
    texture.interpolation = "Linear"
    output.node_tree = _gltf_group()
    base = nodes.get(BLEND)
    x, y = (base.location.x, base.location.y - 700.0) if base is not None else (-600.0, -700.0)
    for i, node in enumerate(made):
        node.location = (x + 200.0 * (i - 2), y)
    links.new(uv.outputs["UV"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], split.inputs["Color"])
    links.new(split.outputs["Red"], output.inputs["Occlusion"])
