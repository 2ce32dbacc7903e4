"""The Geometry Nodes group that reads a mesh's islands (:func:`..operators.adapters.mesh_data.vertex_islands`):
each point's Mesh Island index, stored as the point attribute :data:`ISLAND_ATTRIBUTE`."""

from .raycast_nodes import geometry_group

#: The point attribute the group stores each vertex's island in (on the evaluated copy only).
ISLAND_ATTRIBUTE = "seamless_ao_island"


def island_group(name):
    """A new Geometry Nodes group ``name`` storing each point's island index (Blender's Mesh Island node: points
    joined by edges) as the integer point attribute :data:`ISLAND_ATTRIBUTE`."""
    group, group_in, group_out = geometry_group(name)
    nodes, links = group.nodes, group.links
    island = nodes.new("GeometryNodeInputMeshIsland")
    store = nodes.new("GeometryNodeStoreNamedAttribute")
    store.data_type = "INT"
    store.domain = "POINT"
    store.inputs["Name"].default_value = ISLAND_ATTRIBUTE
    links.new(group_in.outputs[0], store.inputs["Geometry"])
    links.new(island.outputs["Island Index"], store.inputs["Value"])
    links.new(store.outputs["Geometry"], group_out.inputs[0])
    return group
