"""AO on objects whose modifiers change the topology, or that share a mesh: the stack stays live.

The UV maps AO_X/Y/Z cannot live on such an object's base mesh (its corners
are not the ones that render).  Instead a bake keeps what it saw: a *helper*
mesh with the evaluated mesh's corners, in the evaluated order, and the three
UV maps on them, held by a helper object in no scene.  A Geometry Nodes
modifier, ``Seamless AO``, last in the stack, stores those UV maps onto the
evaluated mesh by corner index, where the materials' UV Map nodes read them.

When the stack no longer gives the surface that was baked (its point, face
or corner count differs: a modifier was changed, or the viewport's
Subdivision level is not the render's), the modifier stores no UV maps and a
``seamless_ao_stale`` attribute of 1 instead, and the node group shows no AO
there, never AO read through UV maps that do not fit.
"""

import bpy
import numpy as np

from ...core.keys import (AO_LAYERS, HELPER_KEY, HELPER_PREFIX, STACK_GROUP, STACK_MODIFIER, STACK_VERSION,
                          STACK_VERSION_KEY, STALE_ATTRIBUTE)
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


def _build(group):
    group.nodes.clear()
    group.interface.clear()
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    helper = group.interface.new_socket("Baked", in_out="INPUT", socket_type="NodeSocketObject")
    helper.description = "What the bake saw: the evaluated mesh's corners and the AO UV maps on them"
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = group.nodes, group.links
    inputs, outputs = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    info = nodes.new("GeometryNodeObjectInfo")
    info.transform_space = "ORIGINAL"
    links.new(inputs.outputs["Baked"], info.inputs["Object"])
    # fits: the same number of points, faces and corners as what was baked
    fits = None
    sizes = []
    for source in (inputs.outputs["Geometry"], info.outputs["Geometry"]):
        size = nodes.new("GeometryNodeAttributeDomainSize")
        size.component = "MESH"
        links.new(source, size.inputs["Geometry"])
        sizes.append(size)
    for name in ("Point Count", "Face Count", "Face Corner Count"):
        equal = nodes.new("FunctionNodeCompare")
        equal.data_type, equal.operation = "INT", "EQUAL"
        first, second = (next(s for s in equal.inputs if s.name == side and s.type == "INT") for side in "AB")
        links.new(sizes[0].outputs[name], first)        # by name and type: 5.2 shows only the chosen type's
        links.new(sizes[1].outputs[name], second)
        if fits is None:
            fits = equal.outputs[0]
        else:
            both = nodes.new("FunctionNodeBooleanMath")
            both.operation = "AND"
            links.new(fits, both.inputs[0])
            links.new(equal.outputs[0], both.inputs[1])
            fits = both.outputs[0]
    # the UV maps, corner by corner
    geometry = inputs.outputs["Geometry"]
    index = nodes.new("GeometryNodeInputIndex")
    for layer in AO_LAYERS:
        named = nodes.new("GeometryNodeInputNamedAttribute")
        named.data_type = "FLOAT_VECTOR"
        named.inputs["Name"].default_value = layer
        sample = nodes.new("GeometryNodeSampleIndex")
        sample.data_type, sample.domain = "FLOAT_VECTOR", "CORNER"
        links.new(info.outputs["Geometry"], sample.inputs["Geometry"])
        links.new(named.outputs["Attribute"], sample.inputs[1])
        links.new(index.outputs["Index"], sample.inputs["Index"])
        store = nodes.new("GeometryNodeStoreNamedAttribute")
        store.data_type, store.domain = "FLOAT2", "CORNER"
        store.inputs["Name"].default_value = layer
        links.new(geometry, store.inputs["Geometry"])
        links.new(sample.outputs[0], store.inputs["Value"])
        geometry = store.outputs["Geometry"]
    stale = nodes.new("GeometryNodeStoreNamedAttribute")
    stale.data_type, stale.domain = "FLOAT", "POINT"
    stale.inputs["Name"].default_value = STALE_ATTRIBUTE
    stale.inputs["Value"].default_value = 1.0
    links.new(inputs.outputs["Geometry"], stale.inputs["Geometry"])
    switch = nodes.new("GeometryNodeSwitch")
    switch.input_type = "GEOMETRY"
    links.new(fits, switch.inputs["Switch"])
    links.new(stale.outputs["Geometry"], switch.inputs["False"])
    links.new(geometry, switch.inputs["True"])
    links.new(switch.outputs[0], outputs.inputs["Geometry"])
    for k, node in enumerate(nodes):
        node.location = (200.0 * (k % 8), -200.0 * (k // 8))


def helper_mesh(name, topology, layer_uv_per_corner):
    """A new mesh with the baked corners (``topology``: :class:`.mesh_data.Topology`) and UV maps AO_X/Y/Z
    from ``layer_uv_per_corner`` (3, l, 2)."""
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


def baked_socket(modifier):
    """The identifier of the modifier's ``Baked`` input (the helper object goes there)."""
    return next(item.identifier for item in modifier.node_group.interface.items_tree
                if getattr(item, "in_out", None) == "INPUT" and item.name == "Baked")


def baked_input(modifier):
    """The helper object the modifier reads (None if none)."""
    socket = baked_socket(modifier)
    interface = getattr(getattr(modifier, "properties", None), "inputs", None)
    if interface is not None:                              # Blender 5.2: inputs are RNA, not ID properties
        return getattr(interface, socket).value
    return modifier.get(socket)


def set_baked_input(modifier, helper):
    """Point the modifier at ``helper``."""
    socket = baked_socket(modifier)
    interface = getattr(getattr(modifier, "properties", None), "inputs", None)
    if interface is not None:
        getattr(interface, socket).value = helper
    else:
        modifier[socket] = helper


def remove_helper(helper):
    """Remove a helper object and its mesh (once nothing else uses them)."""
    mesh = helper.data
    bpy.data.objects.remove(helper)
    if mesh is not None and mesh.users == 0:
        bpy.data.meshes.remove(mesh)


def helper_name(ob):
    return HELPER_PREFIX + ob.name
