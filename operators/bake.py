"""``object.seamless_ao_bake``: bake Seamless AO for the selected meshes."""

import bpy

from ..core.errors import SeamlessAOError
from .properties import setting_annotations, settings_from
from . import api


class OBJECT_OT_seamless_ao_bake(bpy.types.Operator):
    """Bake ambient occlusion for the selected meshes: no unwrap needed, no seams"""

    bl_idname = "object.seamless_ao_bake"
    bl_label = "Bake Seamless AO"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = setting_annotations()

    @classmethod
    def poll(cls, context):
        problem = api.selection_problem(context)
        if problem:
            cls.poll_message_set(problem)
            return False
        return True

    def execute(self, context):
        try:
            settings = settings_from(context.scene.seamless_ao, overrides=self)
            report = api.bake(api.target_objects(context), settings=settings, context=context)
        except SeamlessAOError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, report.summary())
        return {"FINISHED"}
