"""The Python API: ``bake(objects, **settings) -> BakeReport`` and ``clear(objects)``.

The bake operator, the command line and pipeline scripts all go through
:class:`BakeSession`, which reads the meshes, runs the core pipeline and only
then writes into Blender data, in one transaction: if anything fails or the
bake is cancelled, every mesh, UV map, material and image is left exactly as
it was.

    import bl_ext.user_default.seamless_ao as seamless_ao
    report = seamless_ao.bake([bpy.data.objects["Suzanne"]], rays=128, image_size=2048)
    print(report.summary())
"""

import dataclasses
import hashlib
import os
import time
import zlib

import bpy
import numpy as np

from ..core.ao import ORIGIN_OFFSET, AOParams, BVHCaster, noise_bound, ray_space
from ..core.denoise import denoise
from ..core.errors import BakeCancelled, SeamlessAOError
from ..core.pipeline import AOJob, build_layout, estimated_bytes, texel_image
from ..core.settings import BakeSettings
from ..shaders import material as material_nodes
from ..shaders.node_group import GROUP_VERSION, VERSION_KEY, find_node_group, node_group as build_node_group
from .mesh_data import read_triangles
from .raycast_nodes import NodesCaster

AO_LAYERS = material_nodes.UV_NAMES
#: Blender allows this many UV maps per mesh.
MAX_UV_MAPS = 8
#: Custom properties the bake leaves on what it made, so Clear and re-bakes find them.
IMAGE_KEY = "seamless_ao_image"              # on objects: name of their AO image
MATERIAL_KEY = "seamless_ao_material"        # on objects: a material the bake created for them
OURS_KEY = "seamless_ao"                     # on images: made by Seamless AO

#: Test hook: set to a step name ("image", "uv_maps", "materials") to make the
#: write phase fail right after that step, as a crash would.
inject_failure = None


# -- selection ------------------------------------------------------------------

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


# -- report -----------------------------------------------------------------------

@dataclasses.dataclass
class BakeReport:
    """What a bake did (also stored on the scene for the panel)."""

    objects: list
    image: str
    width: int
    height: int
    texels: int
    rays: int
    utilisation: float
    density: float
    charts: int
    seconds: float
    timings: dict
    mesh_problems: list
    warnings: list
    caster: str
    noise: float = 0.0

    def summary(self):
        text = "Baked {} in {:.1f} s: {}x{} image '{}', {:,} texels, {:,.0f} rays, {:.0%} of the image used".format(
            ", ".join(self.objects), self.seconds, self.width, self.height, self.image, self.texels, self.rays,
            self.utilisation)
        text += ", noise before denoising at most {:.3f}".format(self.noise)
        if self.mesh_problems:
            text += "; handled: " + ", ".join(self.mesh_problems)
        return text


# -- checks -------------------------------------------------------------------------

def check_objects(objects, settings):
    """Raise :class:`SeamlessAOError` with one clear sentence for input that cannot be baked."""
    if not objects:
        raise SeamlessAOError("Select a mesh object to bake")
    seen_meshes = {}
    for ob in objects:
        if ob is None or ob.type != "MESH":
            raise SeamlessAOError("'{}' is not a mesh; Seamless AO bakes mesh objects only".format(
                getattr(ob, "name", ob)))
        if ob.library is not None or ob.data.library is not None:
            raise SeamlessAOError("'{}' is linked from a library and cannot be changed; make it local first".format(
                ob.name))
        if ob.mode == "EDIT":
            raise SeamlessAOError("'{}' is in Edit Mode; press Tab to leave it before baking".format(ob.name))
        if ob.data.name in seen_meshes:
            raise SeamlessAOError(
                "'{}' and '{}' share one mesh, so they would share UV maps; bake one of them, or make the mesh "
                "single-user".format(seen_meshes[ob.data.name], ob.name))
        seen_meshes[ob.data.name] = ob.name
        if not len(ob.data.polygons):
            raise SeamlessAOError("'{}' has no faces to bake (only vertices or loose edges)".format(ob.name))
        if flattened(ob.matrix_world):
            raise SeamlessAOError(
                "'{}' is scaled to zero along an axis (its own or a parent's scale), so it has no surface to "
                "bake; give it a non-zero scale".format(ob.name))
        others = [uv.name for uv in ob.data.uv_layers if uv.name not in AO_LAYERS]
        if len(others) + len(AO_LAYERS) > MAX_UV_MAPS:
            raise SeamlessAOError(
                "'{}' already has {} UV maps; Blender allows {} and Seamless AO needs 3 more (AO_X, AO_Y, AO_Z): "
                "remove {} to bake".format(ob.name, len(others), MAX_UV_MAPS,
                                           len(others) + len(AO_LAYERS) - MAX_UV_MAPS))
    if settings.save_image != "NONE" and not bpy.data.filepath:
        raise SeamlessAOError("Save the .blend file first: the AO image is written next to it")


def mesh_fingerprint(ob):
    """What a bake's writes rely on, cheaply: the object's mesh, its counts, a checksum of its vertex
    positions and of its loops' vertices (a few ms for a million vertices)."""
    mesh = ob.data
    positions = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", positions)
    loop_vertices = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertices)
    return (mesh.as_pointer(), len(mesh.vertices), len(mesh.loops), len(mesh.polygons),
            zlib.crc32(positions.tobytes()), zlib.crc32(loop_vertices.tobytes()))


def flattened(matrix_world):
    """Whether a world matrix squashes space flat: its smallest singular value is under 1e-9 of its largest."""
    singular = np.linalg.svd(np.array(matrix_world.to_3x3(), dtype=np.float64), compute_uv=False)
    return not singular[-1] > 1e-9 * singular[0]


def evaluated_mesh_of(ob, depsgraph):
    """The evaluated (modifiers applied) mesh of ``ob``, or a clear error if the modifiers change topology."""
    evaluated = ob.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    base = ob.data
    if (len(mesh.vertices), len(mesh.loops), len(mesh.polygons)) != (
            len(base.vertices), len(base.loops), len(base.polygons)):
        evaluated.to_mesh_clear()
        changing = [m.name for m in ob.modifiers if m.show_viewport] or ["(geometry nodes or shape)"]
        raise SeamlessAOError(
            "'{}': the modifiers {} change the mesh's topology, so the AO UV maps could not follow them; apply "
            "them or turn them off in the viewport (deforming modifiers are fine)".format(
                ob.name, ", ".join(changing)))
    return evaluated, mesh


# -- the session ---------------------------------------------------------------------

class BakeSession:
    """One bake, step by step.

    ``for fraction, message in session.steps(): ...`` runs it; the operator
    does one step per timer event.  :meth:`cancel` (or an exception) cleans up
    and leaves all user data as it was.  After the last step, ``report`` holds
    the :class:`BakeReport`.
    """

    def __init__(self, objects, settings, scene=None, depsgraph=None):
        self.objects = list(objects)
        self.settings = settings
        self.scene = scene or bpy.context.scene
        self.depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
        self.casters = []
        self.report = None
        self.started = time.perf_counter()
        check_objects(self.objects, settings)

    # Each step is a generator stage; steps() chains them.
    def steps(self):
        try:
            yield 0.0, "Reading meshes"
            meshes, frames = self._read_meshes()
            self._check_memory(meshes)
            yield 0.05, "Building charts and atlas"
            layout = build_layout(
                meshes, self.settings.compare_angle,
                image_size=self.settings.image_size if self.settings.size_mode == "IMAGE_SIZE" else None,
                density=self.settings.texel_density if self.settings.size_mode == "DENSITY" else None,
                padding=self.settings.padding)
            self._check_memory(meshes, layout)
            yield 0.15, "Preparing rays"
            parts = [self._ray_part(frame, mesh) for frame, mesh in zip(frames, meshes)]
            job = AOJob(layout, parts)
            while not job.finished:
                fraction = job.step()
                yield 0.15 + 0.8 * fraction, "Casting rays: {:.0%}".format(fraction)
            ao_seconds = job.seconds
            self._free_casters()
            ao = job.ao
            noise = noise_bound(ao[job.computed], self.settings.rays)
            if self.settings.denoise:
                yield 0.95, "Denoising"
                start = time.perf_counter()
                ao = denoise(layout.texels, layout.atlas, layout.mesh, ao, job.computed, self.settings.rays)
                layout.timings["denoise"] = time.perf_counter() - start
            yield 0.96, "Writing image, UV maps and materials"
            self._check_unchanged()
            image = texel_image(layout.texels, ao, job.computed)
            warnings = list(layout.atlas.warnings) + self._write(layout, image)
            timings = dict(layout.timings, rays=ao_seconds)
            self.report = BakeReport(
                objects=[ob.name for ob in self.objects], image=self.image_name, width=layout.atlas.width,
                height=layout.atlas.height, texels=job.total, rays=job.rays_cast,
                utilisation=layout.atlas.utilisation, density=layout.atlas.density, charts=layout.charts.count,
                seconds=time.perf_counter() - self.started, timings=timings,
                mesh_problems=layout.topology.report.problems(), warnings=warnings,
                caster=parts[0][1].name, noise=noise)
            store_stats(self.scene, self.report)
            yield 1.0, "Done"
        finally:
            self._free_casters()

    def run(self, should_cancel=None, progress=None):
        """All steps at once; returns the report (raises :class:`BakeCancelled` if asked to stop)."""
        steps = self.steps()
        try:
            for fraction, message in steps:
                if progress is not None:
                    progress(fraction, message)
                if should_cancel is not None and should_cancel() and fraction < 1.0:
                    raise BakeCancelled()
        finally:
            steps.close()
        return self.report

    def cancel(self):
        self._free_casters()

    # -- stages ---------------------------------------------------------------

    def _read_meshes(self):
        meshes, frames = [], []
        for ob in self.objects:
            evaluated, mesh = evaluated_mesh_of(ob, self.depsgraph)
            try:
                triangle_mesh, loops = read_triangles(mesh)
            finally:
                evaluated.to_mesh_clear()
            meshes.append(triangle_mesh)
            frames.append((ob, loops, np.array(ob.matrix_world, dtype=np.float64)))
        self.frames = frames
        self.fingerprints = [mesh_fingerprint(ob) for ob in self.objects]
        return meshes, frames

    def _check_unchanged(self):
        """Refuse to write if a baked object was deleted, edited or put in Edit Mode since it was read
        (the interactive bake lets the user work meanwhile; undo also replaces objects)."""
        for ob, fingerprint in zip(self.objects, self.fingerprints):
            try:
                name = ob.name
                changed = ob.mode == "EDIT" or mesh_fingerprint(ob) != fingerprint
            except ReferenceError:
                raise SeamlessAOError(
                    "An object being baked was deleted or undone during the bake; nothing was written") from None
            if changed:
                raise SeamlessAOError(
                    "'{}' was edited during the bake, so the AO no longer fits its mesh; nothing was written: "
                    "bake again".format(name))

    def _check_memory(self, meshes, layout=None):
        if layout is None:
            if self.settings.size_mode == "IMAGE_SIZE":
                pixels = self.settings.image_size**2
            else:
                area = sum(float(m.triangle_area.sum()) for m in meshes) * 1.5
                pixels = area * self.settings.texel_density**2 / 0.5
            texels = pixels * 0.8
        else:
            pixels, texels = layout.atlas.width * layout.atlas.height, len(layout.texels)
        needed = estimated_bytes(texels, pixels) / 2**20
        if needed > self.settings.memory_budget_mb:
            raise SeamlessAOError(
                "This bake would need about {:,.0f} MB, more than the memory budget of {:,} MB; lower the image "
                "size or texel density, or raise the budget".format(needed, self.settings.memory_budget_mb))

    def _ray_part(self, frame, mesh):
        params, caster, to_ray = ray_setup(frame[0], mesh, self.settings, self.scene, self.depsgraph)
        self.casters.append(caster)
        return params, caster, to_ray

    def _free_casters(self):
        for caster in self.casters:
            if hasattr(caster, "free"):
                caster.free()
        self.casters = []

    # -- writing ---------------------------------------------------------------

    def default_image_name(self):
        """``<object>_AO``, or for several objects one name made of theirs."""
        names = sorted(ob.name for ob in self.objects)
        if len(names) == 1:
            return names[0] + "_AO"
        joined = "+".join(names)
        if len(joined) > 50:
            joined = joined[:40] + "-" + hashlib.sha1(joined.encode()).hexdigest()[:8]
        return joined + "_AO"

    def _write(self, layout, image_values):
        """Image, UV maps, node group, materials: all or nothing."""
        transaction = Transaction()
        warnings = []
        try:
            image = transaction.image(self.default_image_name(), image_values)
            self.image_name = image.name
            _fail_here("image")
            layer_uv = layout.atlas.layer_uv()
            offsets = np.concatenate([[0], np.cumsum(np.bincount(layout.part_of_triangle,
                                                                 minlength=len(self.objects)))])
            for part, (ob, loops, _) in enumerate(self.frames):
                part_uv = layer_uv[offsets[part]:offsets[part + 1]]
                transaction.uv_maps(ob.data, loops, part_uv)
            _fail_here("uv_maps")
            transaction.node_group()
            for ob in self.objects:
                warnings += transaction.materials(ob, image, self.settings.hook_materials, self.objects)
                transaction.set_property(ob, IMAGE_KEY, image.name)
            _fail_here("materials")
            if self.settings.save_image != "NONE":
                transaction.file(image_file_path(image, self.settings.save_image),
                                 lambda path: save_image_file(path, image, image_values, self.settings.save_image))
            _fail_here("saved")
        except BaseException:
            transaction.roll_back()
            raise
        transaction.commit()
        return warnings


def ray_setup(ob, mesh, settings, scene, depsgraph, rays=None):
    """AO parameters, caster and ray-space map for one object.

    Ray space has the world's axes and scale (what the object looks like)
    with the object's bounding-box centre at the origin, so positions stay
    small for float32 BVHs even far from the world origin.  The caller frees
    the caster (``caster.free()`` where it has one).
    """
    matrix = np.array(ob.matrix_world, dtype=np.float64)
    centre, to_ray = ray_space(mesh.positions, matrix[:3, :3])
    own = to_ray(mesh.positions)
    size = float(np.linalg.norm(own.max(axis=0) - own.min(axis=0))) or 1.0
    positions, triangles = [own], [mesh.triangles]
    if settings.use_scene_occluders:
        shift = matrix[:3, :3] @ centre + matrix[:3, 3]
        for world_positions, other_triangles in scene_occluders(scene, depsgraph, exclude=ob):
            triangles.append(other_triangles + sum(len(p) for p in positions))
            positions.append(world_positions - shift)
    params = AOParams(
        rays=settings.rays if rays is None else rays,
        max_distance=0.5 * size if settings.auto_distance else settings.max_distance,
        cone_angle=settings.cone_angle, falloff=settings.falloff, distribution=settings.distribution,
        ignore_backfaces=settings.ignore_backfaces, horizon_bias=settings.horizon_bias,
        adaptive=settings.adaptive, seed=settings.seed, offset=ORIGIN_OFFSET * size,
        ground_height=float(own[:, 2].min()) if settings.use_ground_plane else None)
    positions, triangles = np.concatenate(positions), np.concatenate(triangles)
    caster = (BVHCaster if settings.ray_caster == "PYTHON_BVH" else NodesCaster)(positions, triangles)
    return params, caster, to_ray


def scene_occluders(scene, depsgraph, exclude):
    """(world positions, triangles) of every visible mesh of the scene but ``exclude``."""
    for other in scene.objects:
        if other is exclude or other.type != "MESH" or not other.visible_get():
            continue
        evaluated = other.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        try:
            mesh.calc_loop_triangles()
            count = len(mesh.loop_triangles)
            if not count:
                continue
            co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
            mesh.vertices.foreach_get("co", co)
            tris = np.empty(count * 3, dtype=np.int32)
            mesh.loop_triangles.foreach_get("vertices", tris)
        finally:
            evaluated.to_mesh_clear()
        matrix = np.array(other.matrix_world, dtype=np.float64)
        world = co.reshape(-1, 3).astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
        yield world, tris.reshape(-1, 3).astype(np.int64)


def _fail_here(step):
    if inject_failure == step:
        raise RuntimeError("injected failure after step '{}'".format(step))


class Transaction:
    """Writes into Blender data, each with the action that undoes it."""

    def __init__(self):
        self.undo = []
        self.undo_first = []            # undone before the rest: the node group, before its users
        self.on_commit = []

    def roll_back(self):
        for action in self.undo_first + self.undo[::-1]:
            action()
        self.undo.clear()
        self.undo_first.clear()
        self.on_commit.clear()

    def commit(self):
        """Everything was written: drop what was kept only for a roll-back."""
        for action in self.on_commit:
            action()
        self.on_commit.clear()
        self.undo.clear()
        self.undo_first.clear()

    def node_group(self):
        """The current ``Seamless AO`` group.  An older one is rebuilt in place; until the bake is
        committed a copy of the old one is kept, so a roll-back puts it back for every material."""
        group = find_node_group()
        if group is None:
            self.undo.append(_remove_node_group_if_unused)
        elif group.get(VERSION_KEY) != GROUP_VERSION:
            backup = group.copy()
            del backup[VERSION_KEY]                   # not found as ours meanwhile

            def restore(group=group, backup=backup, name=group.name, version=group[VERSION_KEY]):
                group.user_remap(backup)
                bpy.data.node_groups.remove(group)
                backup.name = name
                backup[VERSION_KEY] = version
            # first: the materials, restored afterwards, relink to the old group's sockets; their
            # snapshots are taken now, since rebuilding the group drops their links to it
            self.undo_first.append(restore)
            for material in bpy.data.materials:
                if material.node_tree is not None and any(
                        n.bl_idname == "ShaderNodeGroup" and n.node_tree == group for n in material.node_tree.nodes):
                    self.undo.append(MaterialSnapshot(material).restore)
            self.on_commit.append(lambda backup=backup: bpy.data.node_groups.remove(backup))
        return build_node_group()

    def file(self, path, write):
        """``write(path)``, undone by putting back the file that was there (or removing the new one)."""
        old = None
        if os.path.exists(path):
            with open(path, "rb") as handle:
                old = handle.read()

        def restore(path=path, old=old):
            if old is None:
                if os.path.exists(path):
                    os.remove(path)
            else:
                with open(path, "wb") as handle:
                    handle.write(old)
        self.undo.append(restore)
        write(path)

    def set_property(self, owner, key, value):
        """``owner[key] = value``, undone by restoring (or deleting) the old value."""
        old = owner.get(key)

        def restore(owner=owner, key=key, old=old):
            if old is None:
                owner.pop(key, None)
            else:
                owner[key] = old
        self.undo.append(restore)
        owner[key] = value

    def image(self, name, values):
        """The AO image, new or (if the add-on made it) overwritten in place; packed into the .blend."""
        height, width = values.shape
        pixels = np.empty((height * width, 4), dtype=np.float32)
        pixels[:, :3] = values.reshape(-1, 1)
        pixels[:, 3] = 1.0
        image = bpy.data.images.get(name)
        if image is not None and image.get(OURS_KEY):
            old_size = tuple(image.size)
            old_pixels = np.empty(len(image.pixels), dtype=np.float32)
            image.pixels.foreach_get(old_pixels)
            _regenerate(image, width, height)

            def restore(image=image, size=old_size, pixels=old_pixels):
                _regenerate(image, *size)
                image.pixels.foreach_set(pixels)
                image.pack()
            self.undo.append(restore)
        else:
            image = bpy.data.images.new(name, width, height, alpha=False, float_buffer=True)
            image[OURS_KEY] = True
            self.undo.append(lambda image=image: bpy.data.images.remove(image))
        if image.colorspace_settings.name != "Non-Color":
            image.colorspace_settings.name = "Non-Color"
        image.pixels.foreach_set(pixels.ravel())
        image.pack()
        return image

    def uv_maps(self, mesh, loops, layer_uv):
        """Create or replace AO_X/Y/Z; the user's active and render-active UV maps stay as they were.

        Parameters
        ----------
        loops : (t, 3) int, loop of each triangle corner
        layer_uv : (t, 3 layers, 3 corners, 2)
        """
        layers = mesh.uv_layers
        active = layers.active.name if layers.active is not None else None
        render = next((uv.name for uv in layers if uv.active_render), None)
        for axis, name in enumerate(AO_LAYERS):
            uv = np.zeros((len(mesh.loops), 2), dtype=np.float32)
            uv[loops.ravel()] = layer_uv[:, axis].reshape(-1, 2)
            layer = layers.get(name)
            if layer is None:
                layer = layers.new(name=name, do_init=False)
                self.undo.append(lambda mesh=mesh, name=name: mesh.uv_layers.remove(mesh.uv_layers[name]))
            else:
                old = np.empty(len(mesh.loops) * 2, dtype=np.float32)
                layer.data.foreach_get("uv", old)
                self.undo.append(lambda mesh=mesh, name=name, old=old: mesh.uv_layers[name].data.foreach_set("uv", old))
            layer.data.foreach_set("uv", uv.ravel())
        self.undo.append(lambda mesh=mesh, active=active, render=render: _restore_active(mesh, active, render))
        _restore_active(mesh, active, render)

    def materials(self, ob, image, multiply, baked_objects):
        """Hook every material of ``ob`` (giving it one if it has none)."""
        warnings = []
        if not any(slot.material for slot in ob.material_slots):
            material = material_nodes.new_material(ob.name + "_SeamlessAO")
            if ob.material_slots:
                old = ob.material_slots[0].material
                ob.material_slots[0].material = material
                self.undo.append(lambda ob=ob, old=old: setattr(ob.material_slots[0], "material", old))
            else:
                ob.data.materials.append(material)
                self.undo.append(lambda mesh=ob.data: mesh.materials.pop())
            self.undo.append(lambda material=material: bpy.data.materials.remove(material))
            self.set_property(ob, MATERIAL_KEY, material.name)
        baked_meshes = {o.data for o in baked_objects}
        for material in {slot.material for slot in ob.material_slots if slot.material is not None}:
            if material.library is not None:
                warnings.append("material '{}' is linked from a library and was left alone".format(material.name))
                continue
            snapshot = MaterialSnapshot(material)
            material_nodes.hook_material(material, image, multiply)
            self.undo.append(snapshot.restore)
            sharers = [o.name for o in bpy.data.objects if o.type == "MESH" and o.data not in baked_meshes
                       and any(s.material == material for s in o.material_slots) and o.get(IMAGE_KEY)]
            if sharers:
                warnings.append("material '{}' is also used by {}, baked separately: it now shows this bake's "
                                "image; bake them together to share one".format(material.name, ", ".join(sharers)))
        return warnings


def _regenerate(image, width, height):
    """Turn a (packed) image back into a generated float buffer of the given size, keeping the datablock."""
    image.source = "GENERATED"
    image.generated_width, image.generated_height = width, height
    image.use_generated_float = True


def _remove_node_group_if_unused():
    group = find_node_group()
    if group is not None and group.users == 0:
        bpy.data.node_groups.remove(group)


def _restore_active(mesh, active, render):
    layers = mesh.uv_layers
    if active is not None and active in layers:
        layers.active = layers[active]
    if render is not None and render in layers:
        layers[render].active_render = True


class MaterialSnapshot:
    """Enough of a material's node tree to put it back exactly: the nodes we add and the links we change."""

    def __init__(self, material):
        self.material = material
        self.had_nodes = material_nodes.uses_nodes(material)
        self.keys = {k: material[k] for k in material.keys()}
        tree = material.node_tree
        self.ours = set()
        self.links = []
        self.values = {}
        self.images = {}
        if tree is not None:
            self.ours = {n.name for n in tree.nodes if material_nodes.is_ours(n)}
            self.images = {n.name: n.image for n in tree.nodes
                           if material_nodes.is_ours(n) and n.bl_idname == "ShaderNodeTexImage"}
            self.links = [(l.from_node.name, l.from_socket.identifier, l.to_node.name, l.to_socket.identifier)
                          for l in tree.links]
            for node in tree.nodes:
                if node.bl_idname == "ShaderNodeBsdfPrincipled":
                    self.values[node.name] = tuple(node.inputs["Base Color"].default_value)

    def restore(self):
        material = self.material
        tree = material.node_tree
        if tree is not None:
            for node in [n for n in tree.nodes if material_nodes.is_ours(n) and n.name not in self.ours]:
                tree.nodes.remove(node)
            for link in list(tree.links):
                tree.links.remove(link)
            for from_node, from_socket, to_node, to_socket in self.links:
                source, target = tree.nodes.get(from_node), tree.nodes.get(to_node)
                if source is not None and target is not None:
                    tree.links.new(material_nodes._socket(source.outputs, from_socket),
                                   material_nodes._socket(target.inputs, to_socket))
            for name, value in self.values.items():
                tree.nodes[name].inputs["Base Color"].default_value = value
            for name, image in self.images.items():
                if tree.nodes.get(name) is not None:
                    tree.nodes[name].image = image
        for key in [k for k in material.keys() if k not in self.keys]:
            del material[key]
        if material_nodes.uses_nodes(material) != self.had_nodes:
            material.use_nodes = self.had_nodes


def image_file_path(image, kind):
    """Where ``save_image`` writes: next to the .blend, named after the image."""
    folder = os.path.dirname(bpy.path.abspath(bpy.data.filepath))
    return os.path.join(folder, image.name + (".png" if kind == "PNG" else ".exr"))


def save_image_file(path, image, values, kind):
    """Write the AO to ``path``: 16-bit greyscale PNG or 32-bit float OpenEXR."""
    if kind == "PNG":
        write_png16(path, values)
    else:
        copy = bpy.data.images.new(".SeamlessAO_save", image.size[0], image.size[1], alpha=False, float_buffer=True)
        try:
            copy.colorspace_settings.name = "Non-Color"
            pixels = np.repeat(values.reshape(-1, 1), 4, axis=1).astype(np.float32)
            pixels[:, 3] = 1.0
            copy.pixels.foreach_set(pixels.ravel())
            copy.filepath_raw = path
            copy.file_format = "OPEN_EXR"
            copy.save()
        finally:
            bpy.data.images.remove(copy)


def write_png16(path, values):
    """A 16-bit greyscale PNG of ``values`` (height, width) in [0, 1]; row 0 is the bottom (Blender's order)."""
    height, width = values.shape
    data = np.round(np.clip(values[::-1], 0.0, 1.0) * 65535.0).astype(">u2")
    raw = b"".join(b"\x00" + row.tobytes() for row in data)

    def chunk(kind, payload):
        return (len(payload).to_bytes(4, "big") + kind + payload
                + zlib.crc32(kind + payload).to_bytes(4, "big"))

    header = width.to_bytes(4, "big") + height.to_bytes(4, "big") + bytes([16, 0, 0, 0, 0])
    with open(path, "wb") as handle:
        handle.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 6))
                     + chunk(b"IEND", b""))


def store_stats(scene, report):
    """The last bake's numbers, for the panel."""
    props = getattr(scene, "seamless_ao", None)
    if props is None:
        return
    props.last_bake_summary = report.summary()
    props.last_bake_time = report.seconds
    props.last_bake_texels = report.texels
    props.last_bake_rays = float(report.rays)
    props.last_bake_utilisation = report.utilisation
    props.last_bake_noise = report.noise


# -- public functions -------------------------------------------------------------------

def bake(objects, settings=None, scene=None, should_cancel=None, progress=None, **overrides):
    """Bake Seamless AO for ``objects`` (one shared image if several).

    Parameters
    ----------
    objects : list of bpy.types.Object
    settings : BakeSettings, optional
        Defaults to the scene's Seamless AO settings (or the built-in defaults
        when the add-on's properties are not registered).
    scene : bpy.types.Scene, optional
    should_cancel : callable, optional
        Polled between steps; return True to stop (raises BakeCancelled).
    progress : callable ``(fraction, message)``, optional
    **overrides
        Any :class:`~..core.settings.BakeSettings` field, e.g. ``rays=128``.

    Returns
    -------
    BakeReport
    """
    scene = scene or bpy.context.scene
    if settings is None:
        props = getattr(scene, "seamless_ao", None)
        if props is not None:
            from .properties import settings_from
            settings = settings_from(props)
        else:
            settings = BakeSettings()
    if overrides:
        settings = settings.replace(**overrides)
    session = BakeSession(objects, settings, scene=scene)
    return session.run(should_cancel, progress)


def clear(objects):
    """Remove exactly what bakes added to ``objects``: UV maps, nodes, created materials, unused images.

    Returns the number of objects that had anything to remove.
    """
    cleared = 0
    for ob in objects:
        if ob is None or ob.type != "MESH":
            continue
        touched = False
        mesh = ob.data
        for name in AO_LAYERS:
            layer = mesh.uv_layers.get(name)
            if layer is not None:
                mesh.uv_layers.remove(layer)
                touched = True
        for material in {slot.material for slot in ob.material_slots if slot.material is not None}:
            if material.node_tree is not None and any(material_nodes.is_ours(n) for n in material.node_tree.nodes):
                material_nodes.unhook_material(material)
                touched = True
        created = ob.get(MATERIAL_KEY)
        if created:
            material = bpy.data.materials.get(created)
            if material is not None and material.get(material_nodes.CREATED_KEY):
                index = mesh.materials.find(material.name)
                if index >= 0:
                    mesh.materials.pop(index=index)
                if material.users == 0:
                    bpy.data.materials.remove(material)
            del ob[MATERIAL_KEY]
            touched = True
        from .export import clear_exports
        touched |= clear_exports(ob)
        image_name = ob.get(IMAGE_KEY)
        if image_name:
            image = bpy.data.images.get(image_name)
            if image is not None and image.get(OURS_KEY) and image.users == 0:
                bpy.data.images.remove(image)
            del ob[IMAGE_KEY]
            touched = True
        cleared += touched
    group = find_node_group()
    if group is not None and group.users == 0:
        bpy.data.node_groups.remove(group)
    return cleared


def set_preview(objects, enabled):
    """Show only the baked AO on these objects' materials (or put their surfaces back)."""
    changed = 0
    for ob in objects:
        for material in {slot.material for slot in getattr(ob, "material_slots", []) if slot.material is not None}:
            changed += bool(material_nodes.set_preview(material, enabled))
    return changed


def poll_explained(operator_class, problem):
    """What ``poll`` returns for ``problem`` (a sentence, or ``""``): False with the sentence as the tooltip."""
    if problem:
        operator_class.poll_message_set(problem)
        return False
    return True


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
