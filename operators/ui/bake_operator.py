"""``object.seamless_ao_bake``: bake Seamless AO for the selected meshes.

From the UI it runs modal on a timer: one step of work per ``TIMER`` event, a
progress bar and a status line, ESC cancels and leaves everything as it was.
From a script or in ``--background`` it runs to completion synchronously.
"""

import traceback

import bpy

from ...core.errors import BakeCancelled, SeamlessAOError
from ..adapters.scene_settings import settings_from
from ..adapters.session import BakeSession
from .poll import poll_explained, selection_problem, target_objects
from .properties import setting_annotations


class OBJECT_OT_seamless_ao_bake(bpy.types.Operator):
    """Bake ambient occlusion for the selected meshes: no unwrap needed, no seams"""

    bl_idname = "object.seamless_ao_bake"
    bl_label = "Bake Seamless AO"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = setting_annotations()

    @classmethod
    def poll(cls, context):
        return poll_explained(cls, selection_problem(context))

    def _session(self, context):
        settings = settings_from(context.scene.seamless_ao, overrides=self)
        return BakeSession(target_objects(context), settings, scene=context.scene)

    def execute(self, context):
        try:
            report = self._session(context).run()
        except BakeCancelled as error:
            self.report({"WARNING"}, str(error))
            return {"CANCELLED"}
        except SeamlessAOError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except Exception as error:                      # a bug: say so in one sentence, details to the console
            traceback.print_exc()
            self.report({"ERROR"}, "Seamless AO failed unexpectedly ({}); nothing was changed".format(error))
            return {"CANCELLED"}
        self._finish_report(report)
        return {"FINISHED"}

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        try:
            self.session = self._session(context)
        except SeamlessAOError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.steps = self.session.steps()
        window_manager = context.window_manager
        window_manager.progress_begin(0, 100)
        self.timer = window_manager.event_timer_add(0.02, window=context.window)
        window_manager.modal_handler_add(self)
        self._status(context, "Seamless AO: starting (Esc to cancel)")
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self.cancel(context)
            self.report({"WARNING"}, "Seamless AO bake cancelled; nothing was changed")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        try:
            fraction, message = next(self.steps)
        except StopIteration:
            fraction, message = 1.0, "Done"
        except SeamlessAOError as error:
            self.cancel(context)
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except Exception as error:
            traceback.print_exc()
            self.cancel(context)
            self.report({"ERROR"}, "Seamless AO failed unexpectedly ({}); nothing was changed".format(error))
            return {"CANCELLED"}
        context.window_manager.progress_update(int(100 * fraction))
        self._status(context, "Seamless AO: {} (Esc to cancel; editing a baked object also cancels)".format(message))
        if fraction >= 1.0 and self.session.report is not None:
            self._end(context)
            self._finish_report(self.session.report)
            return {"FINISHED"}
        return {"RUNNING_MODAL"}

    def cancel(self, context):
        self.steps.close()                              # runs the session's clean-up
        self.session.cancel()
        self._end(context)

    def _end(self, context):
        window_manager = context.window_manager
        window_manager.event_timer_remove(self.timer)
        window_manager.progress_end()
        self._status(context, None)
        for area in context.screen.areas if context.screen else []:
            area.tag_redraw()

    @staticmethod
    def _status(context, text):
        if context.workspace is not None:
            context.workspace.status_text_set(text)

    def _finish_report(self, report):
        self.report({"INFO"}, report.summary())
        for warning in report.warnings:
            self.report({"WARNING"}, warning)
