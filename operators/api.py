"""The Python API: ``bake(objects, **settings) -> BakeReport``.

The operator, the command line and pipeline scripts all call :func:`bake`.
"""

from ..core.errors import SeamlessAOError


def target_objects(context):
    """The selected mesh objects, or the active one if nothing is selected."""
    selected = [ob for ob in context.selected_objects if ob.type == "MESH"]
    if selected:
        return selected
    active = context.active_object
    return [active] if active is not None and active.type == "MESH" else []


def selection_problem(context):
    """A sentence saying why nothing can be baked now, or ``""``."""
    if not target_objects(context):
        return "Select a mesh object to bake"
    return ""


def bake(objects, settings=None, context=None, **kwargs):
    raise SeamlessAOError("The bake pipeline is not built yet")
