"""What the two export operators share: a baked mesh must be selected (``poll``), settings the caller
did not set come from the scene's Export panel (``invoke``), and an export error is one sentence."""

from ..core.errors import SeamlessAOError
from .poll import baked_selection_problem, poll_explained
from .properties import export_annotations, fill_from_scene


class ExportOperator:
    """Mix-in for an operator with ``fields`` (names of ``ExportSettings`` it has as properties, made here from
    core's settings) and ``export(context) -> message``."""

    bl_options = {"REGISTER", "UNDO"}
    fields = ()

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        cls.__annotations__ = export_annotations(cls.fields)

    @classmethod
    def poll(cls, context):
        missing = "Bake Seamless AO first: the selected meshes have no bake to export"
        return poll_explained(cls, baked_selection_problem(context, missing))

    def invoke(self, context, event):
        fill_from_scene(self, context.scene.seamless_ao, self.fields)
        return self.execute(context)

    def execute(self, context):
        try:
            message = self.export(context)
        except SeamlessAOError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, message)
        return {"FINISHED"}
