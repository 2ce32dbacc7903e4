"""``object.seamless_ao_clear``: remove exactly what bakes added to the selected meshes."""

import bpy

from .adapters.clearing import clear
from .poll import baked_selection_problem, poll_explained, target_objects


class OBJECT_OT_seamless_ao_clear(bpy.types.Operator):
    """Remove the AO UV maps, nodes, images and materials Seamless AO added to the selected meshes"""

    bl_idname = "object.seamless_ao_clear"
    bl_label = "Clear Seamless AO"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return poll_explained(
            cls, baked_selection_problem(context, "The selected meshes have no Seamless AO bake to clear"))

    def execute(self, context):
        count = clear(target_objects(context))
        self.report({"INFO"}, "Cleared Seamless AO from {} object{}".format(count, "" if count == 1 else "s"))
        return {"FINISHED"}
