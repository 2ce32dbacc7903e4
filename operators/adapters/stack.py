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
of its faces through one baked chart (:mod:`...core.atlas.viewport_uv`); the
modifier's ``Viewport`` input points at it.  The modifier's node group is
built in :mod:`...shaders.stack_nodes`, with every other node tree.

When the stack gives neither surface (its point, face or corner count
differs: a modifier was changed after the bake), the modifier stores no UV
maps and a ``seamless_ao_stale`` attribute of 1 instead, and the node group
shows no AO there, never AO read through UV maps that do not fit.
"""

import bpy
import numpy as np

from ...core.keys import AO_LAYERS, HELPER_KEY, HELPER_PREFIX, STACK_INPUTS, STACK_MODIFIER, STACK_VERSION_KEY
from .mesh_data import write_uv


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
