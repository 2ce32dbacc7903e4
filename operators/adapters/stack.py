"""AO on objects whose modifiers change the topology, or that share a mesh: the stack stays live.

The UV maps AO_X/Y/Z cannot live on such an object's base mesh (its corners
are not the ones that render).  Instead a bake keeps what it saw: a *helper*
mesh with the evaluated mesh's corners, in the evaluated order, and the three
UV maps on them, held by a helper object in no scene.  A Geometry Nodes
modifier, ``Seamless AO``, last in the stack, stores those UV maps onto the
evaluated mesh by corner index, where the materials' UV Map nodes read them.

Where the viewport's levels differ from the render's (Blender's default
Subdivision: 1 in the viewport, 2 at render), a second helper holds the
viewport surface's corners as the bake saw them, with UV maps that read each
of its faces through one baked chart (:mod:`...core.viewport_uv`); the
modifier's ``Viewport`` input points at it.

When the stack gives neither surface (its point, face or corner count
differs: a modifier was changed after the bake), the modifier stores no UV
maps and a ``seamless_ao_stale`` attribute of 1 instead, and the node group
shows no AO there, never AO read through UV maps that do not fit.
"""

import bpy
import numpy as np

from ...core.keys import (AO_LAYERS, HELPER_KEY, HELPER_PREFIX, STACK_GROUP, STACK_INPUTS, STACK_MODIFIER,
                          STACK_VERSION, STACK_VERSION_KEY, STALE_ATTRIBUTE)
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


def helper_mesh(name, corners, layer_uv_per_corner):
    """A new mesh with the corners of ``corners`` (:class:`.mesh_data.EvaluatedCorners`) and UV maps AO_X/Y/Z from
    ``layer_uv_per_corner`` (3, l, 2)."""
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(corners.positions))
    mesh.attributes["position"].data.foreach_set("vector", np.ascontiguousarray(corners.positions).ravel())
    mesh.loops.add(len(corners.corner_vert))
    if ".corner_vert" in mesh.attributes:
        mesh.attributes[".corner_vert"].data.foreach_set("value", corners.corner_vert)
    else:
        mesh.loops.foreach_set("vertex_index", corners.corner_vert)
    mesh.polygons.add(len(corners.loop_start))
    mesh.polygons.foreach_set("loop_start", corners.loop_start)
    mesh.update(calc_edges=True)
    for layer, uv in zip(AO_LAYERS, layer_uv_per_corner):
        mesh.uv_layers.new(name=layer, do_init=False)
        write_uv(mesh, layer, uv)
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
    """The identifier of the modifier's input ``name``, or None (a group from an older version lacks it)."""
    return next((item.identifier for item in modifier.node_group.interface.items_tree
                 if getattr(item, "in_out", None) == "INPUT" and item.name == name), None)


def _inputs_of(modifier):
    """Blender 5.2 keeps a modifier's inputs as RNA (``properties.inputs``), earlier ones as ID properties."""
    return getattr(getattr(modifier, "properties", None), "inputs", None)


def helper_inputs(modifier):
    """The helper objects the modifier reads: (baked, viewport), each None if none."""
    interface = _inputs_of(modifier)
    found = []
    for name in STACK_INPUTS:
        socket = _input_identifier(modifier, name)
        if socket is None:
            found.append(None)
        else:
            found.append(getattr(interface, socket).value if interface is not None else modifier.get(socket))
    return tuple(found)


def baked_input(modifier):
    """The helper object with the baked surface that the modifier reads (None if none)."""
    return helper_inputs(modifier)[0]


def set_helper_inputs(modifier, baked, viewport=None):
    """Point the modifier at the helper of the baked surface and that of the viewport's (or None)."""
    interface = _inputs_of(modifier)
    for name, value in zip(STACK_INPUTS, (baked, viewport)):
        socket = _input_identifier(modifier, name)
        if socket is None:
            continue
        if interface is not None:
            getattr(interface, socket).value = value
        else:
            modifier[socket] = value


def viewport_helper_of(ob):
    """The helper of the viewport's surface that ``ob``'s Seamless AO modifier reads, or None."""
    modifier = stack_modifier(ob)
    return helper_inputs(modifier)[1] if modifier is not None else None


def helpers_of(ob):
    """``(baked, viewport)``: the helpers an earlier bake left for ``ob``, each None if none."""
    return helper_of(ob), viewport_helper_of(ob)


def remove_helper(helper):
    """Remove a helper object and its mesh (once nothing else uses them); None: nothing."""
    if helper is None:
        return
    mesh = helper.data
    bpy.data.objects.remove(helper)
    if mesh is not None and mesh.users == 0:
        bpy.data.meshes.remove(mesh)


def helper_name(ob, viewport=False):
    return HELPER_PREFIX + ob.name + (" viewport" if viewport else "")
