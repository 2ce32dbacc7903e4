"""The shader node group ``Seamless AO``: three lookups blended by the squared normal.

Structure (shader groups cannot take an image as an input, so each material
holds the image lookups and the group only does the math):

    material:   UV Map AO_X -> Image Texture (the object's AO image) -> group input "AO X"
                UV Map AO_Y -> Image Texture                         -> group input "AO Y"
                UV Map AO_Z -> Image Texture                         -> group input "AO Z"
                Attribute seamless_ao_stale (0 where absent)         -> group input "Stale"
    group:      Texture Coordinate > Normal (object space) n
                w = (nx², ny², nz²) / (nx² + ny² + nz²)
                ao = w.x * AO X + w.y * AO Y + w.z * AO Z
                ao' = ao / (1 - c (1 - ao))          (RTR §9.2.4 interreflection, c = Interreflection)
                AO = max(1 - Strength * (1 - ao'), Stale)

So one group serves every object and every material; each material's Image
Texture nodes point at its object's image (objects baked together share one
image, so a material shared by them works).  The group is versioned: an older
group is rebuilt in place, so materials that use it keep working.
"""

import bpy

from ..core.keys import GROUP_NAME, GROUP_VERSION, VERSION_KEY


def find_node_group():
    """The group this add-on made (found by its version key, whatever it is called now), or None."""
    ours = [g for g in bpy.data.node_groups if g.bl_idname == "ShaderNodeTree" and VERSION_KEY in g]
    return min(ours, key=lambda g: g.name) if ours else None


def node_group():
    """The ``Seamless AO`` group, built, or rebuilt in place if older than this add-on's."""
    group = find_node_group()
    if group is None:
        group = bpy.data.node_groups.new(GROUP_NAME, "ShaderNodeTree")
    elif group[VERSION_KEY] == GROUP_VERSION:
        return group
    _build(group)
    group[VERSION_KEY] = GROUP_VERSION
    return group


def _new_socket(group, name, in_out, kind, default=None, low=None, high=None, description=""):
    socket = group.interface.new_socket(name, in_out=in_out, socket_type=kind)
    socket.description = description
    if default is not None:
        socket.default_value = default
    if low is not None:
        socket.min_value = low
    if high is not None:
        socket.max_value = high
    return socket


def _build(group):
    group.nodes.clear()
    group.interface.clear()
    for axis in "XYZ":
        _new_socket(group, "AO " + axis, "INPUT", "NodeSocketFloat", 1.0, 0.0, 1.0,
                "The AO image read through UV map AO_" + axis)
    _new_socket(group, "Strength", "INPUT", "NodeSocketFloat", 1.0, 0.0, 1.0, "0 = no AO, 1 = full AO")
    _new_socket(group, "Interreflection", "INPUT", "NodeSocketFloat", 0.0, 0.0, 0.95,
            "Brighten AO for light bounced between surfaces (RTR 9.2.4): ao / (1 - c (1 - ao))")
    _new_socket(group, "Stale", "INPUT", "NodeSocketFloat", 0.0, 0.0, 1.0,
            "1 where the modifier stack no longer gives the surface that was baked: no AO is shown there")
    _new_socket(group, "AO", "OUTPUT", "NodeSocketFloat", description="Ambient occlusion, 1 = open, 0 = occluded")
    nodes, links = group.nodes, group.links

    def math(operation, a=None, b=None, c=None, x=0.0, clamp=False):
        node = nodes.new("ShaderNodeMath")
        node.operation = operation
        node.use_clamp = clamp
        node.location = (x, 0)
        for socket, value in zip(node.inputs, (a, b, c)):
            if value is None:
                continue
            if isinstance(value, (int, float)):
                socket.default_value = value
            else:
                links.new(value, socket)
        return node.outputs[0]

    inputs = nodes.new("NodeGroupInput")
    inputs.location = (-900, 0)
    outputs = nodes.new("NodeGroupOutput")
    outputs.location = (900, 0)
    coordinates = nodes.new("ShaderNodeTexCoord")
    coordinates.location = (-900, -300)
    square = nodes.new("ShaderNodeVectorMath")
    square.operation = "MULTIPLY"
    square.location = (-700, -300)
    links.new(coordinates.outputs["Normal"], square.inputs[0])
    links.new(coordinates.outputs["Normal"], square.inputs[1])
    split = nodes.new("ShaderNodeSeparateXYZ")
    split.location = (-500, -300)
    links.new(square.outputs["Vector"], split.inputs[0])
    total = math("ADD", math("ADD", split.outputs["X"], split.outputs["Y"], x=-300), split.outputs["Z"], x=-200)
    total = math("MAXIMUM", total, 1e-12, x=-100)
    blended = None
    for axis in "XYZ":
        weight = math("DIVIDE", split.outputs[axis], total, x=0)
        blended = math("MULTIPLY_ADD", weight, inputs.outputs["AO " + axis], blended if blended is not None else 0.0,
                       x=150)
    open_part = math("SUBTRACT", 1.0, blended, x=300)
    denominator = math("SUBTRACT", 1.0, math("MULTIPLY", inputs.outputs["Interreflection"], open_part, x=400), x=450)
    brightened = math("DIVIDE", blended, denominator, x=500, clamp=True)
    darkening = math("MULTIPLY", inputs.outputs["Strength"], math("SUBTRACT", 1.0, brightened, x=600), x=650)
    result = math("SUBTRACT", 1.0, darkening, x=750, clamp=True)
    # stale: 1 (no AO) instead of AO read through UV maps that no longer fit the surface
    shown = math("MAXIMUM", result, inputs.outputs["Stale"], x=850)
    links.new(shown, outputs.inputs["AO"])
