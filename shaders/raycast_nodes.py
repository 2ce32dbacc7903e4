"""The ray caster's Geometry Nodes group (:class:`..operators.adapters.casters.NodesCaster`): the points of a
temporary mesh cast rays along their ``ray_dir`` attribute against ``occluder`` and store ``hit`` = (distance
or -1 on a miss, the hit normal's dot with the ray, the ``sealed`` attribute of the face hit)."""

import bpy


def geometry_group(name):
    """A new Geometry Nodes group ``name`` with one geometry in and one out, for a temporary evaluation:
    ``(group, its Group Input node, its Group Output node)``."""
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    return group, group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")


def raycast_group(name, occluder):
    """A new Geometry Nodes group ``name`` casting against object ``occluder``: ``(group, its Raycast node)``
    (whose Ray Length the caster sets for each batch)."""
    group, group_in, group_out = geometry_group(name)
    nodes, links = group.nodes, group.links
    target = nodes.new("GeometryNodeObjectInfo")
    target.inputs["Object"].default_value = occluder
    direction = nodes.new("GeometryNodeInputNamedAttribute")
    direction.data_type = "FLOAT_VECTOR"
    direction.inputs["Name"].default_value = "ray_dir"
    sealed = nodes.new("GeometryNodeInputNamedAttribute")
    sealed.data_type = "FLOAT"
    sealed.inputs["Name"].default_value = "sealed"
    cast = nodes.new("GeometryNodeRaycast")
    cast.data_type = "FLOAT"
    links.new(target.outputs["Geometry"], cast.inputs["Target Geometry"])
    links.new(sealed.outputs["Attribute"], cast.inputs["Attribute"])
    links.new(direction.outputs["Attribute"], cast.inputs["Ray Direction"])
    miss = nodes.new("GeometryNodeSwitch")
    miss.input_type = "FLOAT"
    miss.inputs["False"].default_value = -1.0
    links.new(cast.outputs["Is Hit"], miss.inputs["Switch"])
    links.new(cast.outputs["Hit Distance"], miss.inputs["True"])
    facing = nodes.new("ShaderNodeVectorMath")
    facing.operation = "DOT_PRODUCT"
    links.new(cast.outputs["Hit Normal"], facing.inputs[0])
    links.new(direction.outputs["Attribute"], facing.inputs[1])
    # One stored vector (distance, facing, sealed): one field evaluation, so
    # the rays are cast once (two stores would evaluate the raycast twice).
    combine = nodes.new("ShaderNodeCombineXYZ")
    links.new(miss.outputs[0], combine.inputs["X"])
    links.new(facing.outputs["Value"], combine.inputs["Y"])
    links.new(cast.outputs["Attribute"], combine.inputs["Z"])
    store = nodes.new("GeometryNodeStoreNamedAttribute")
    store.data_type = "FLOAT_VECTOR"
    store.inputs["Name"].default_value = "hit"
    links.new(group_in.outputs[0], store.inputs["Geometry"])
    links.new(combine.outputs["Vector"], store.inputs["Value"])
    links.new(store.outputs["Geometry"], group_out.inputs[0])
    return group, cast
