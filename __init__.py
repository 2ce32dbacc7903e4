"""Seamless AO: bake ambient occlusion for any mesh in one click.

No UV unwrap by the user and no visible seams: faces are clustered into
overlapping charts along the six signed axes, AO is ray-cast for every texel
at its exact surface point, and a node group blends three lookups with the
squared object-space normal.  See README.md.

Python API (also what the operator and the command line use)::

    from bl_ext.user_default import seamless_ao
    report = seamless_ao.bake([obj], rays=128)
    seamless_ao.resample([obj], uv_map="UVMap", size=2048)     # glTF-ready texture
    seamless_ao.to_color_attribute([obj])                      # colour attribute "AO"
    seamless_ao.clear([obj])
    seamless_ao.batch(["assets/"], output_dir="baked/")        # asset files, in worker processes

The package must be imported with relative imports only: Blender loads it as
``bl_ext.<repository>.seamless_ao``, the tests under another name.
"""

from . import operators, panels
from .core.errors import BakeCancelled, SeamlessAOError
from .core.settings import BakeSettings
from .operators.adapters.clearing import clear
from .operators.adapters.exports import resample, to_color_attribute
from .operators.adapters.preview import set_preview
from .operators.adapters.session import BakeReport, bake
from .operators.batch.runner import batch

__all__ = ["bake", "batch", "clear", "set_preview", "resample", "to_color_attribute", "BakeSettings", "BakeReport",
           "SeamlessAOError", "BakeCancelled"]


def register():
    operators.register()
    panels.register()


def unregister():
    panels.unregister()
    operators.unregister()
