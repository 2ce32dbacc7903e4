"""AO on objects whose modifiers change the topology, or that share a mesh: the stack stays live.

The UV maps AO_X/Y/Z cannot live on such an object's base mesh (its corners
are not the ones that render).  Instead a bake keeps what it saw: a *helper*
mesh with the evaluated mesh's corners, in the evaluated order, and the three
UV maps on them, held by a helper object in no scene.  A Geometry Nodes
modifier, ``Seamless AO``, last in the stack, stores those UV maps onto the
evaluated mesh by corner index, where the materials' UV Map nodes read them.

Where the viewport's levels differ from the render's (Blender's default
Subdivision: 1 in the viewport, 2 at render), the modifier finds the
viewport's surface by its counts at the bake (the modifier's ``Viewport …``
inputs) and gives each of its faces the UV map of the baked face nearest its
centre (:mod:`...core.viewport_uv`), evaluated at its own corners.

When the stack gives neither surface (its point, face or corner count
differs: a modifier was changed after the bake), the modifier stores no UV
maps and a ``seamless_ao_stale`` attribute of 1 instead, and the node group
shows no AO there, never AO read through UV maps that do not fit.
"""

import bpy
import numpy as np

from ...core.keys import (AO_LAYERS, HELPER_KEY, HELPER_PREFIX, MAP_PREFIX, NEAREST_FACE, STACK_GROUP,
                          STACK_MODIFIER, STACK_VERSION, STACK_VERSION_KEY, STALE_ATTRIBUTE, VIEWPORT_INPUTS)
from ...core.viewport_uv import face_uv_maps
from .mesh_data import write_uv


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


def _build(group):
    group.nodes.clear()
    group.interface.clear()
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    helper = group.interface.new_socket("Baked", in_out="INPUT", socket_type="NodeSocketObject")
    helper.description = "What the bake saw: the evaluated mesh's corners and the AO UV maps on them"
    for name in VIEWPORT_INPUTS:
        count = group.interface.new_socket(name, in_out="INPUT", socket_type="NodeSocketInt")
        count.description = "The viewport surface's count at the bake (its levels may differ from the render's)"
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = group.nodes, group.links
    inputs, outputs = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    info = nodes.new("GeometryNodeObjectInfo")
    info.transform_space = "ORIGINAL"
    links.new(inputs.outputs["Baked"], info.inputs["Object"])
    baked, given = info.outputs["Geometry"], inputs.outputs["Geometry"]
    sizes = []
    for source in (given, baked):
        size = nodes.new("GeometryNodeAttributeDomainSize")
        size.component = "MESH"
        links.new(source, size.inputs["Geometry"])
        sizes.append([size.outputs[name] for name in ("Point Count", "Face Count", "Face Corner Count")])
    # what was baked: the UV maps, corner by corner
    fits_baked = _counts_equal(nodes, links, sizes[0], sizes[1])
    index = nodes.new("GeometryNodeInputIndex").outputs["Index"]
    exact = given
    for layer in AO_LAYERS:
        uv = _sample(nodes, links, baked, _named(nodes, layer, "FLOAT_VECTOR"), "FLOAT_VECTOR", "CORNER", index)
        exact = _store(nodes, links, exact, layer, "FLOAT2", "CORNER", uv)
    # the viewport's surface at the bake: each face reads through the nearest baked face's maps
    fits_viewport = _counts_equal(nodes, links, sizes[0], [inputs.outputs[name] for name in VIEWPORT_INPUTS])
    nearest = nodes.new("GeometryNodeSampleNearest")
    nearest.domain = "FACE"
    links.new(baked, nearest.inputs["Geometry"])
    position = nodes.new("GeometryNodeInputPosition").outputs["Position"]
    links.new(position, nearest.inputs["Sample Position"])   # on the face domain: the face's centre
    near = _store(nodes, links, given, NEAREST_FACE, "INT", "FACE", nearest.outputs["Index"])
    face = _named(nodes, NEAREST_FACE, "INT")
    for layer in AO_LAYERS:
        rows = []
        for row in "uv":
            name = MAP_PREFIX + layer[-1] + "_" + row
            linear = _sample(nodes, links, baked, _named(nodes, name, "FLOAT_VECTOR"), "FLOAT_VECTOR", "FACE", face)
            shift = _sample(nodes, links, baked, _named(nodes, name + "0", "FLOAT"), "FLOAT", "FACE", face)
            dot = nodes.new("ShaderNodeVectorMath")
            dot.operation = "DOT_PRODUCT"
            links.new(linear, dot.inputs[0])
            links.new(position, dot.inputs[1])
            add = nodes.new("ShaderNodeMath")
            add.operation = "ADD"
            links.new(dot.outputs["Value"], add.inputs[0])
            links.new(shift, add.inputs[1])
            rows.append(add.outputs[0])
        combine = nodes.new("ShaderNodeCombineXYZ")
        links.new(rows[0], combine.inputs["X"])
        links.new(rows[1], combine.inputs["Y"])
        near = _store(nodes, links, near, layer, "FLOAT2", "CORNER", combine.outputs["Vector"])
    remove = nodes.new("GeometryNodeRemoveAttribute")
    remove.inputs["Name"].default_value = NEAREST_FACE
    links.new(near, remove.inputs["Geometry"])
    # neither: a stale mark, which the shader group turns into no AO
    stale = nodes.new("GeometryNodeStoreNamedAttribute")
    stale.data_type, stale.domain = "FLOAT", "POINT"
    stale.inputs["Name"].default_value = STALE_ATTRIBUTE
    _value(stale.inputs).default_value = 1.0
    links.new(given, stale.inputs["Geometry"])
    other = _switch(nodes, links, fits_viewport, remove.outputs["Geometry"], stale.outputs["Geometry"])
    links.new(_switch(nodes, links, fits_baked, exact, other), outputs.inputs["Geometry"])
    for k, node in enumerate(nodes):
        node.location = (200.0 * (k % 8), -200.0 * (k // 8))


def helper_mesh(name, topology, layer_uv_per_corner, layer_drop_per_corner):
    """A new mesh with the baked corners (``topology``: :class:`.mesh_data.Topology`), UV maps AO_X/Y/Z
    from ``layer_uv_per_corner`` (3, l, 2), and on its faces each layer's map from position to UV
    (:func:`...core.viewport_uv.face_uv_maps`; ``layer_drop_per_corner`` (3, l): the coordinate each
    corner's chart drops)."""
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(topology.positions))
    mesh.attributes["position"].data.foreach_set("vector", np.ascontiguousarray(topology.positions).ravel())
    mesh.loops.add(len(topology.corner_vert))
    if ".corner_vert" in mesh.attributes:
        mesh.attributes[".corner_vert"].data.foreach_set("value", topology.corner_vert)
    else:
        mesh.loops.foreach_set("vertex_index", topology.corner_vert)
    mesh.polygons.add(len(topology.loop_start))
    mesh.polygons.foreach_set("loop_start", topology.loop_start)
    mesh.update(calc_edges=True)
    for layer, uv in zip(AO_LAYERS, layer_uv_per_corner):
        mesh.uv_layers.new(name=layer, do_init=False)
        write_uv(mesh, layer, uv)
    linear, offset = face_uv_maps(topology.positions, topology.corner_vert, topology.loop_start,
                                  layer_uv_per_corner, layer_drop_per_corner)
    for number, layer in enumerate(AO_LAYERS):
        for row, part in enumerate("uv"):
            name = MAP_PREFIX + layer[-1] + "_" + part
            mesh.attributes.new(name, "FLOAT_VECTOR", "FACE").data.foreach_set(
                "vector", np.ascontiguousarray(linear[number, :, row]).ravel())
            mesh.attributes.new(name + "0", "FLOAT", "FACE").data.foreach_set(
                "value", np.ascontiguousarray(offset[number, :, row]))
    return mesh


def helper_of(ob):
    """The helper object a bake left for ``ob``, or None."""
    name = ob.get(HELPER_KEY)
    return bpy.data.objects.get(name) if name else None


def stack_modifier(ob):
    """``ob``'s Seamless AO modifier (ours: named so, running our group), or None."""
    modifier = ob.modifiers.get(STACK_MODIFIER)
    if modifier is not None and modifier.type == "NODES" and modifier.node_group is not None and (
            STACK_VERSION_KEY in modifier.node_group):
        return modifier
    return None


def _input_identifier(modifier, name):
    return next(item.identifier for item in modifier.node_group.interface.items_tree
                if getattr(item, "in_out", None) == "INPUT" and item.name == name)


def baked_socket(modifier):
    """The identifier of the modifier's ``Baked`` input (the helper object goes there)."""
    return _input_identifier(modifier, "Baked")


def baked_input(modifier):
    """The helper object the modifier reads (None if none)."""
    socket = baked_socket(modifier)
    interface = getattr(getattr(modifier, "properties", None), "inputs", None)
    if interface is not None:                              # Blender 5.2: inputs are RNA, not ID properties
        return getattr(interface, socket).value
    return modifier.get(socket)


def set_baked_input(modifier, helper, viewport_counts=(0, 0, 0)):
    """Point the modifier at ``helper``, and give it the viewport surface's counts at the bake."""
    for name, value in zip(("Baked",) + VIEWPORT_INPUTS, (helper,) + tuple(int(c) for c in viewport_counts)):
        socket = _input_identifier(modifier, name)
        interface = getattr(getattr(modifier, "properties", None), "inputs", None)
        if interface is not None:                          # Blender 5.2: inputs are RNA, not ID properties
            getattr(interface, socket).value = value
        else:
            modifier[socket] = value


def viewport_counts(modifier):
    """The viewport counts the modifier holds."""
    interface = getattr(getattr(modifier, "properties", None), "inputs", None)
    identifiers = [_input_identifier(modifier, name) for name in VIEWPORT_INPUTS]
    if interface is not None:
        return tuple(getattr(interface, socket).value for socket in identifiers)
    return tuple(modifier.get(socket, 0) for socket in identifiers)


def remove_helper(helper):
    """Remove a helper object and its mesh (once nothing else uses them)."""
    mesh = helper.data
    bpy.data.objects.remove(helper)
    if mesh is not None and mesh.users == 0:
        bpy.data.meshes.remove(mesh)


def helper_name(ob):
    return HELPER_PREFIX + ob.name
