"""Every name Seamless AO stores Blender data under: UV maps, custom properties, node and group names.

A leaf with no imports: the Blender side (``operators/``, ``shaders/``) and the
batch read their names here, so a re-bake, Clear and an export find exactly
what an earlier bake wrote, and nothing else can be mistaken for it.
"""

# -- what a bake writes on the mesh ------------------------------------------------
AXES = ("X", "Y", "Z")
#: The three UV maps a bake writes (one per axis).
AO_LAYERS = tuple("AO_" + axis for axis in AXES)
#: Blender allows this many UV maps per mesh.
MAX_UV_MAPS = 8

# -- custom properties ---------------------------------------------------------------
IMAGE_KEY = "seamless_ao_image"              # on objects: name of their AO image
MATERIAL_KEY = "seamless_ao_material"        # on objects: a material the bake created for them
OURS_KEY = "seamless_ao"                     # on images: made by Seamless AO
SURFACE_KEY = "seamless_ao_surface"          # on materials: "node|socket identifier" feeding the output before preview
CREATED_KEY = "seamless_ao_created"          # on materials: the add-on made this material (object had none)
NODES_KEY = "seamless_ao_enabled_nodes"      # on materials: the add-on switched use_nodes on

# -- objects whose modifiers change the topology (or that share a mesh): AO through a modifier ----------
STACK_MODIFIER = "Seamless AO"               # the Geometry Nodes modifier, last in the stack
STACK_GROUP = "Seamless AO UVs"              # its node group (found by STACK_VERSION_KEY)
STACK_VERSION = 3
STACK_VERSION_KEY = "seamless_ao_stack_version"   # on that node group
HELPER_KEY = "seamless_ao_helper"            # on objects: the object holding what their bake saw
HELPER_PREFIX = ".SeamlessAO "               # the helper object and mesh (in no scene)
STALE_ATTRIBUTE = "seamless_ao_stale"        # 1 where the stack no longer gives what was baked: no AO shown
#: The stack group's object inputs: the helper with the baked surface's corners, and the helper with the
#: viewport surface's corners where the viewport's levels differ from the render's (core/atlas/viewport_uv.py).
STACK_INPUTS = ("Baked", "Viewport")

# -- the shader nodes ------------------------------------------------------------------
GROUP_NAME = "Seamless AO"                   # the node group (found by VERSION_KEY whatever it is called now)
GROUP_VERSION = 2
VERSION_KEY = "seamless_ao_version"          # on the node group
NODE_PREFIX = "SeamlessAO "                  # every node the add-on adds to a material
FRAME = NODE_PREFIX + "Frame"
BLEND = NODE_PREFIX + "Blend"
PREVIEW = NODE_PREFIX + "Preview"
STALE_NODE = NODE_PREFIX + "Stale"

# -- what the exports write (Clear removes it too) ---------------------------------------
COLOR_ATTRIBUTE = "AO"
EXPORT_KEY = "seamless_ao_export"            # on images and on the glTF group
COLOR_KEY = "seamless_ao_color"              # on objects: the AO colour attribute is ours
GLTF_GROUP = "glTF Material Output"
GLTF_NODES = tuple(NODE_PREFIX + "glTF " + part for part in ("UV", "Image", "Split", "Output"))
#: The UV map a batch makes for the AO when an asset's own cannot hold it (glTF TEXCOORD_1).
AO_UV = "AO_UV"

# -- temporary data, never left behind ---------------------------------------------------
TEMP_PREFIX = ".SeamlessAO_temp_"            # the ray caster's scene, meshes and node group
SAVE_COPY = ".SeamlessAO_save"               # the image copy written as OpenEXR
