"""What the operators' ``poll`` asks: which objects a click would use, and why nothing can be done now."""

from ..core.keys import AO_LAYERS, HELPER_KEY, IMAGE_KEY, STALE_ATTRIBUTE


def target_objects(context):
    """The selected mesh objects, or the active one if nothing is selected."""
    selected = [ob for ob in context.selected_objects if ob.type == "MESH"]
    if selected:
        return selected
    active = context.active_object
    return [active] if active is not None and active.type == "MESH" else []


def selection_problem(context):
    """A sentence saying why nothing can be baked now, or ``""``."""
    if context.mode != "OBJECT":
        return "Switch to Object Mode to bake"
    if not target_objects(context):
        return "Select a mesh object to bake"
    return ""


def baked_selection_problem(context, missing):
    """:func:`selection_problem`, or ``missing`` if none of the selected meshes has a bake."""
    problem = selection_problem(context)
    if not problem and not any(has_bake(ob) for ob in target_objects(context)):
        problem = missing
    return problem


def has_bake(ob):
    """True if ``ob`` carries anything a bake added."""
    if ob is None or ob.type != "MESH":
        return False
    return bool(ob.get(IMAGE_KEY)) or any(name in ob.data.uv_layers for name in AO_LAYERS)


def baked_targets(context):
    """The target objects that have a bake."""
    return [ob for ob in target_objects(context) if has_bake(ob)]


def stale_bakes(context):
    """The target objects whose AO the viewport does not show because their modifier stack, as the viewport
    evaluates it, gives another surface than the one baked (the stack's modifier marks it stale)."""
    depsgraph = context.evaluated_depsgraph_get()
    stale = []
    for ob in target_objects(context):
        if ob.get(HELPER_KEY):
            mesh = ob.evaluated_get(depsgraph).data
            if mesh is not None and STALE_ATTRIBUTE in mesh.attributes:
                stale.append(ob)
    return stale


def poll_explained(operator_class, problem):
    """What ``poll`` returns for ``problem`` (a sentence, or ``""``): False with the sentence as the tooltip."""
    if problem:
        operator_class.poll_message_set(problem)
        return False
    return True
