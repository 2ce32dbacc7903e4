"""Does a change keep every bake and export the same, bit for bit?  Bakes a fixed set of scenes with two
versions of the add-on and compares the images and UV maps they write, and the exports of every baked
object with a UV map of its own (the resampled PNG in each packing, the colour attribute on corners and points).

    .venv/5.0/bin/python tests/scripts/same_images.py --against REV     # this tree against commit REV
    .venv/5.0/bin/python tests/scripts/same_images.py --root DIR --json # one tree's digests (used by the above)

``--against`` checks REV out into a temporary git worktree and runs this
script once per tree, each in a process of its own with that tree's package
(loaded from its folder), on the same scenes built here with bpy and numpy
only: Suzanne, a room of boxes with scene occluders and a ground plane, three
objects baked together (one mirrored, one rotated), the generated interior,
weighted rays, and the Python BVH caster.  It prints one row per scene and
exits with 1 if any image, UV map or export differs.
"""

import argparse
import hashlib
import importlib.util
import json
import os
import pathlib
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve()
SUPPORT = HERE.parents[1] / "support"


def load(root):
    """The add-on in ``root`` as the package ``seamless_ao`` (its own loader: an older tree may have none)."""
    spec = importlib.util.spec_from_file_location("seamless_ao", root / "__init__.py",
                                                  submodule_search_locations=[str(root)])
    package = importlib.util.module_from_spec(spec)
    sys.modules["seamless_ao"] = package
    spec.loader.exec_module(package)
    return package


def mesh_object(bpy, name, positions, triangles, smooth=False):
    """A mesh object of arrays (not the tests' own helper, which imports this tree's add-on)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(map(float, p)) for p in positions], [], [tuple(map(int, t)) for t in triangles])
    mesh.validate()
    if smooth:
        mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
        mesh.update()
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def monkey(bpy, name, levels=2):
    bpy.ops.mesh.primitive_monkey_add()
    ob = bpy.context.active_object
    ob.name = name
    modifier = ob.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = levels
    bpy.ops.object.modifier_apply(modifier=modifier.name)
    ob.data.polygons.foreach_set("use_smooth", [True] * len(ob.data.polygons))
    ob.data.update()
    return ob


def textured_material(bpy):
    """A Principled BSDF whose Roughness is the green channel of an image read through "UVMap" (what the ORM
    and Unity packings carry) and whose Metallic is its own value."""
    import numpy as np
    material = bpy.data.materials.new("Textured")
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    principled = next(n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    principled.inputs["Metallic"].default_value = 0.25
    image = bpy.data.images.new("RoughnessMap", 32, 32, float_buffer=True)
    ramp = np.linspace(0.0, 1.0, 32 * 32 * 4, dtype=np.float32)
    image.pixels.foreach_set(ramp)
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    uv_node = nodes.new("ShaderNodeUVMap")
    uv_node.uv_map = "UVMap"
    split = nodes.new("ShaderNodeSeparateColor")
    links.new(uv_node.outputs["UV"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], split.inputs[0])
    links.new(split.outputs["Green"], principled.inputs["Roughness"])
    return material


def export_digest(package, bpy, objects):
    """sha256 of every export of the baked objects that have a UV map of their own ("UVMap"): the resampled
    PNG in each packing, and the colour attribute on corners and on points; "" when none has one."""
    import numpy as np
    digest = hashlib.sha256()
    for ob in [o for o in objects if "UVMap" in o.data.uv_layers]:
        for packing in ("GLTF", "GREY", "ORM", "UNITY_MASK"):
            name, = package.resample([ob], uv_map="UVMap", size=128, packing=packing, gltf_occlusion=False)
            digest.update(bytes(bpy.data.images[name].packed_file.data))
        for domain in ("CORNER", "POINT"):
            package.to_color_attribute([ob], domain=domain)
            attribute = ob.data.color_attributes["AO"]
            colours = np.empty(len(attribute.data) * 4, dtype=np.float32)
            attribute.data.foreach_get("color", colours)
            digest.update(colours.tobytes())
    return digest.hexdigest()[:16] if any("UVMap" in o.data.uv_layers for o in objects) else ""


def scenes(bpy):
    """``(name, build() -> objects, settings)`` of every scene compared."""
    sys.path.insert(0, str(SUPPORT))
    from meshes import box, torus
    from real_assets import interior

    def suzanne():
        ob = monkey(bpy, "Suzanne")
        ob.data.materials.append(textured_material(bpy))
        return [ob]

    def room():
        positions, triangles = box(size=(4.0, 4.0, 0.2), center=(0.0, 0.0, -0.1))
        mesh_object(bpy, "Floor", positions, triangles)                  # a scene occluder, not baked
        positions, triangles = box(size=(1.0, 1.0, 1.0), center=(0.0, 0.0, 0.6), subdivisions=3)
        return [mesh_object(bpy, "Crate", positions, triangles)]

    def together():
        ring = mesh_object(bpy, "Ring", *torus(rings=32, segments=16), smooth=True)
        ring.scale = (-1.0, 1.0, 1.0)
        head = monkey(bpy, "Head", levels=1)
        head.location = (3.0, 0.0, 0.0)
        head.rotation_euler = (0.3, 0.0, 1.2)
        positions, triangles = box(size=(1.0, 2.0, 0.5), center=(0.0, 3.0, 0.0), subdivisions=2)
        return [ring, head, mesh_object(bpy, "Block", positions, triangles)]

    def hall():
        return [mesh_object(bpy, "Interior", *interior())]

    def small():
        ob = monkey(bpy, "Small", levels=1)
        ob.location = (1e4, -2e4, 3.0)
        return [ob]

    base = dict(image_size=256, rays=16, seed=3)
    return [
        ("suzanne", suzanne, base),
        ("suzanne 384², 32 rays, no adaptive", suzanne, dict(base, image_size=384, rays=32, adaptive=False)),
        ("crate on a floor, scene occluders, ground plane", room,
         dict(base, use_scene_occluders=True, use_ground_plane=True)),
        ("three objects together (mirrored, rotated)", together, dict(base, weighted_rays=True)),
        ("interior 512²", hall, dict(base, image_size=512)),
        ("far from the origin, Python BVH, linear falloff", small,
         dict(base, rays=8, ray_caster="PYTHON_BVH", falloff="LINEAR", denoise=False)),
    ]


def digests(root):
    """``{scene: {"image": sha256, "uv": sha256}}`` of every scene baked by the add-on in ``root``."""
    import bpy
    import numpy as np
    package = load(root)
    result = {}
    for name, build, settings in scenes(bpy):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        objects = build()
        bpy.context.view_layer.update()
        report = package.bake(objects, **settings)
        image = bpy.data.images[report.image]
        pixels = np.empty(len(image.pixels), dtype=np.float32)
        image.pixels.foreach_get(pixels)
        uv = hashlib.sha256()
        for ob in objects:
            for layer in ("AO_X", "AO_Y", "AO_Z"):
                values = np.empty(len(ob.data.loops) * 2, dtype=np.float32)
                ob.data.uv_layers[layer].data.foreach_get("uv", values)
                uv.update(values.tobytes())
        result[name] = {"image": hashlib.sha256(pixels.tobytes()).hexdigest()[:16], "uv": uv.hexdigest()[:16],
                        "exports": export_digest(package, bpy, objects), "texels": report.texels,
                        "rays": int(report.rays)}
    return result


def run_tree(root):
    """This script's ``--json`` run on the tree ``root``, in a process of its own."""
    process = subprocess.run([sys.executable, str(HERE), "--root", str(root), "--json"], capture_output=True,
                             text=True)
    if process.returncode != 0:
        raise SystemExit("the bake failed in {}:\n{}".format(root, process.stderr[-3000:]))
    return json.loads(process.stdout.strip().splitlines()[-1])


def compare(revision):
    here = HERE.parents[2]
    with tempfile.TemporaryDirectory(prefix="same_images_") as scratch:
        other = pathlib.Path(scratch) / "tree"
        subprocess.run(["git", "-C", str(here), "worktree", "add", "--detach", "-q", str(other), revision], check=True)
        try:
            before = run_tree(other)
        finally:
            subprocess.run(["git", "-C", str(here), "worktree", "remove", "--force", str(other)], check=True)
    after = run_tree(here)
    same = True
    print("| scene | image | UV maps | exports | texels, rays |")
    print("|---|---|---|---|---|")
    for name in after:
        a, b = before.get(name, {}), after[name]
        rows = [("same" if a.get(k) == b[k] else "DIFFERENT") for k in ("image", "uv", "exports")]
        rows[2] = rows[2] if b["exports"] else "none"
        same &= all(row in ("same", "none") for row in rows)
        print("| {} | {} | {} | {} | {:,}, {:,} |".format(name, *rows, b["texels"], b["rays"]))
    print("{} against {}: {}".format("this tree", revision, "the same bit for bit" if same else "NOT the same"))
    return 0 if same else 1


def remove_session_folder():
    """Blender's session folder of this process, which ``os._exit`` would leave behind: removed by this tree's
    own launcher (:mod:`launch_file`; the trees compared are loaded as packages)."""
    sys.path.insert(0, str(SUPPORT))
    from launch_file import launcher
    launcher().remove_session_folder()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", metavar="REV", help="compare this tree with commit REV")
    parser.add_argument("--root", help="bake with the add-on in this folder and print digests")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    if args.root:
        print(json.dumps(digests(pathlib.Path(args.root).resolve())))
        status = 0
    else:
        status = compare(args.against or "HEAD")
    sys.stdout.flush()
    remove_session_folder()
    os._exit(status)           # the bpy 4.2 module crashes in teardown once a PropertyGroup was registered


if __name__ == "__main__":
    main()
