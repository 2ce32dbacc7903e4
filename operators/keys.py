"""Names Seamless AO gives to what it writes: UV maps, custom properties, the export's attribute and group.

A leaf: every other module may import it, it imports nothing of the Blender side.
"""

from ..shaders.material import UV_NAMES

#: The three UV maps a bake writes (one per axis).
AO_LAYERS = UV_NAMES
#: Blender allows this many UV maps per mesh.
MAX_UV_MAPS = 8

# Custom properties the bake leaves on what it made, so Clear and re-bakes find them.
IMAGE_KEY = "seamless_ao_image"              # on objects: name of their AO image
MATERIAL_KEY = "seamless_ao_material"        # on objects: a material the bake created for them
OURS_KEY = "seamless_ao"                     # on images: made by Seamless AO

# What the export writes (Clear removes it too).
COLOR_ATTRIBUTE = "AO"
EXPORT_KEY = "seamless_ao_export"            # on images and on the glTF group
COLOR_KEY = "seamless_ao_color"              # on objects: the AO colour attribute is ours
GLTF_GROUP = "glTF Material Output"
GLTF_NODES = ("SeamlessAO glTF UV", "SeamlessAO glTF Image", "SeamlessAO glTF Split", "SeamlessAO glTF Output")
