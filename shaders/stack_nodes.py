"""The ``Seamless AO UVs`` Geometry Nodes group of the stack modifier (:mod:`..operators.adapters.stack`).

It stores the helper's UV maps AO_X/Y/Z onto the evaluated mesh by corner
index, the baked surface's or the viewport's, whichever the stack gives; where
it gives neither, a ``seamless_ao_stale`` attribute of 1 instead.
"""

import bpy

from ..core.keys import AO_LAYERS, STACK_GROUP, STACK_INPUTS, STACK_VERSION, STACK_VERSION_KEY, STALE_ATTRIBUTE


def find_stack_group():
    """The stack node group this add-on made (by its version key), or None."""
    ours = [g for g in bpy.data.node_groups if g.bl_idname == "GeometryNodeTree" and STACK_VERSION_KEY in g]
    return min(ours, key=lambda g: g.name) if ours else None


def stack_group():
    """The ``Seamless AO UVs`` Geometry Nodes group, built (or rebuilt, if older) when needed."""
    group = find_stack_group()
    if group is not None and group[STACK_VERSION_KEY] == STACK_VERSION:
        return group
    if group is None:
        group = bpy.data.node_groups.new(STACK_GROUP, "GeometryNodeTree")
    _build(group)
    group[STACK_VERSION_KEY] = STACK_VERSION
    return group


def _value(sockets, name="Value"):
    """The socket ``name`` a node shows (Blender 4.2 keeps one per data type, hidden but the chosen one)."""
    return next(socket for socket in sockets if socket.name == name and socket.enabled)


def _counts_equal(nodes, links, counts, others):
    """A boolean output: the three ``counts`` outputs (points, faces, corners) equal ``others``."""
    fits = None
    for count, other in zip(counts, others):
        equal = nodes.new("FunctionNodeCompare")
        equal.data_type, equal.operation = "INT", "EQUAL"
        first, second = (next(s for s in equal.inputs if s.name == side and s.type == "INT") for side in "AB")
        links.new(count, first)                          # by name and type: 5.2 shows only the chosen type's
        links.new(other, second)
        if fits is None:
            fits = equal.outputs[0]
        else:
            both = nodes.new("FunctionNodeBooleanMath")
            both.operation = "AND"
            links.new(fits, both.inputs[0])
            links.new(equal.outputs[0], both.inputs[1])
            fits = both.outputs[0]
    return fits


def _store(nodes, links, geometry, name, data_type, domain, value):
    store = nodes.new("GeometryNodeStoreNamedAttribute")
    store.data_type, store.domain = data_type, domain
    store.inputs["Name"].default_value = name
    links.new(geometry, store.inputs["Geometry"])
    links.new(value, _value(store.inputs))
    return store.outputs["Geometry"]


def _named(nodes, name, data_type):
    named = nodes.new("GeometryNodeInputNamedAttribute")
    named.data_type = data_type
    named.inputs["Name"].default_value = name
    return named.outputs["Attribute"]


def _sample(nodes, links, source, value, data_type, domain, index):
    sample = nodes.new("GeometryNodeSampleIndex")
    sample.data_type, sample.domain = data_type, domain
    links.new(source, sample.inputs["Geometry"])
    links.new(value, _value(sample.inputs))
    links.new(index, sample.inputs["Index"])
    return _value(sample.outputs)


def _switch(nodes, links, condition, when_true, when_false):
    switch = nodes.new("GeometryNodeSwitch")
    switch.input_type = "GEOMETRY"
    links.new(condition, switch.inputs["Switch"])
    links.new(when_false, switch.inputs["False"])
    links.new(when_true, switch.inputs["True"])
    return switch.outputs[0]


def _corner_uv_maps(nodes, links, given, source):
    """``given`` with the UV maps AO_X/Y/Z of helper geometry ``source``, corner by corner."""
    index = nodes.new("GeometryNodeInputIndex").outputs["Index"]
    for layer in AO_LAYERS:
        uv = _sample(nodes, links, source, _named(nodes, layer, "FLOAT_VECTOR"), "FLOAT_VECTOR", "CORNER", index)
        given = _store(nodes, links, given, layer, "FLOAT2", "CORNER", uv)
    return given


def _build(group):
    group.nodes.clear()
    group.interface.clear()
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    descriptions = ("What the bake saw: the evaluated mesh's corners and the AO UV maps on them",
                    "The viewport's surface at the bake (its levels may differ from the render's) and its UV maps")
    for name, description in zip(STACK_INPUTS, descriptions):
        socket = group.interface.new_socket(name, in_out="INPUT", socket_type="NodeSocketObject")
        socket.description = description
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = group.nodes, group.links
    inputs, outputs = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    given = inputs.outputs["Geometry"]
    sizes, helpers = [], []
    for source in [given] + [inputs.outputs[name] for name in STACK_INPUTS]:
        if source is not given:
            info = nodes.new("GeometryNodeObjectInfo")
            info.transform_space = "ORIGINAL"
            links.new(source, info.inputs["Object"])
            source = info.outputs["Geometry"]
            helpers.append(source)
        size = nodes.new("GeometryNodeAttributeDomainSize")
        size.component = "MESH"
        links.new(source, size.inputs["Geometry"])
        sizes.append([size.outputs[name] for name in ("Point Count", "Face Count", "Face Corner Count")])
    # the surface baked, or the viewport's at the bake: its UV maps by corner index; neither: a stale mark,
    # which the shader group turns into no AO
    stale = nodes.new("GeometryNodeStoreNamedAttribute")
    stale.data_type, stale.domain = "FLOAT", "POINT"
    stale.inputs["Name"].default_value = STALE_ATTRIBUTE
    _value(stale.inputs).default_value = 1.0
    links.new(given, stale.inputs["Geometry"])
    result = stale.outputs["Geometry"]
    for helper, helper_sizes in reversed(list(zip(helpers, sizes[1:]))):
        fits = _counts_equal(nodes, links, sizes[0], helper_sizes)
        result = _switch(nodes, links, fits, _corner_uv_maps(nodes, links, given, helper), result)
    links.new(result, outputs.inputs["Geometry"])
    for k, node in enumerate(nodes):
        node.location = (200.0 * (k % 8), -200.0 * (k // 8))
