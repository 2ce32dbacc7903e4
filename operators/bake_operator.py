"""``object.seamless_ao_bake``: bake Seamless AO for the selected meshes.

From the UI it runs modal on a timer: the meshes are read, the bake itself runs
in a background process of ours (:mod:`..background.client`) while each
``TIMER`` event reads its progress into the progress bar and the status line,
and the outcome is written at the end; ESC ends the process and leaves
everything as it was.  From a script or in ``--background`` it runs to
completion synchronously, in this process.
"""

import traceback

import bpy

from ..core.errors import BakeCancelled, SeamlessAOError
from .adapters.scene_settings import settings_from
from .adapters.session import BakeSession
from .poll import poll_explained, selection_problem, target_objects
from .properties import setting_annotations


class OBJECT_OT_seamless_ao_bake(bpy.types.Operator):
    """Bake ambient occlusion for the selected meshes: no unwrap needed, no seams"""

    bl_idname = "object.seamless_ao_bake"
    bl_label = "Bake Seamless AO"
    # Undo, but no redo panel: Adjust Last Operation would re-run the whole bake at once, frozen.
    bl_options = {"UNDO"}

    __annotations__ = setting_annotations()

    @classmethod
    def poll(cls, context):
        return poll_explained(cls, selection_problem(context))

    def _session(self, context, background=False):
        settings = settings_from(context.scene.seamless_ao, overrides=self)
        return BakeSession(target_objects(context), settings, scene=context.scene, background=background)

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
            self.session = self._session(context, background=True)     # the window stays live meanwhile
        except SeamlessAOError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.steps = self.session.steps()
        self.shown = None
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
        shown = (int(100 * fraction), message)
        if shown != self.shown:                         # the window redraws for each change: only for a change
            self.shown = shown
            context.window_manager.progress_update(shown[0])
            self._status(context, "Seamless AO: {} (Esc to cancel)".format(message))
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
        print(report.summary())                         # the details: the console; the panel's Last bake box
        self.report({"INFO"}, report.headline())
        for warning in report.warnings:
            self.report({"WARNING"}, warning)
