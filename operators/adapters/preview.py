"""``set_preview(objects, enabled)``: show only the baked AO on the objects' materials, or not."""

from ...shaders import material as material_nodes


def set_preview(objects, enabled):
    """Show only the baked AO on these objects' materials (or put their surfaces back)."""
    changed = 0
    for ob in objects:
        for material in {slot.material for slot in getattr(ob, "material_slots", []) if slot.material is not None}:
            changed += bool(material_nodes.set_material_preview(material, enabled))
    return changed
