"""The background half of a bake from Blender's window: ``launch.py bake-worker FOLDER``.

The window's Blender reads the meshes and writes them into ``FOLDER`` (:mod:`...core.other_processes.handoff`), starts
this process (:mod:`.client`) and stays free for the user while it runs core's pipeline with the same
casters a bake in the window would use, writing its progress, then its outcome or why it failed.
Nothing here touches the user's data: the window's Blender writes the outcome.
"""

import traceback

from ...core.errors import SeamlessAOError
from ...core.other_processes.handoff import read_job, write_failure, write_outcome, write_progress
from ...core.pipeline import BakePipeline
from ..adapters.casters import caster_maker, free_casters


def main(argv):
    folder = argv[0]
    try:
        meshes, matrices, occluders, settings, shown = read_job(folder)
        pipeline = BakePipeline(meshes, matrices, settings, caster_maker(settings),
                                occluders, free_casters, shown)
        for fraction, message in pipeline.steps():
            write_progress(folder, fraction, message)
        write_outcome(folder, pipeline.result, len(meshes))
        return 0
    except SeamlessAOError as error:
        write_failure(folder, str(error))
    except Exception as error:                  # a fault of ours: the traceback goes to the process's log
        traceback.print_exc()
        write_failure(folder, "{}: {}".format(type(error).__name__, error), expected=False)
    return 1
